//! The compiler: a checked program's AST to bytecode, names resolved to slots.

pub mod bytecode;
pub mod disasm;

use crate::check::basic::{self, BasicTy};
use crate::check::{expr_type, functions, Ty};
use crate::diag::{Problem, SourceFile};
use crate::registry::{Access, Hook, Kind, Registry, ValueType};
use crate::span::{LineIndex, Span};
use crate::syntax::ast::{
    BinOp, Expr, ExprKind, GearForm, MoveForm, Name, ProgramAst, Stmt, StmtKind, UnOp, Using,
};
use crate::syntax::Dialect;
use bytecode::{BinaryOp, Cmp, MotionCmd, Op, Reg, StartRef, REAL_STORE};
use indexmap::IndexMap;
use std::collections::BTreeMap;

/// Most temporaries one expression may need (lines are limited to fewer tokens than this).
pub const MAX_TEMPS: u32 = 1024;

/// The value array shared by all programs of a machine.
#[derive(Debug, Clone)]
pub struct Layout {
    /// Registry slots come first.
    pub slot_count: u32,
    /// Constants and loop limits after the temporaries, with their initial values.
    pub extra: Vec<f64>,
    const_index: BTreeMap<u64, Reg>,
    /// String literals (MotionBASIC); a string value is its index here.
    pub strings: Vec<String>,
}

impl Layout {
    /// A layout after the registry's slots.
    pub fn new(registry: &Registry) -> Layout {
        Layout {
            slot_count: registry.slot_count() as u32,
            extra: Vec::new(),
            const_index: BTreeMap::new(),
            strings: Vec::new(),
        }
    }

    /// The value standing for a string literal.
    pub fn string(&mut self, s: &str) -> f64 {
        let i = match self.strings.iter().position(|x| x == s) {
            Some(i) => i,
            None => {
                self.strings.push(s.to_string());
                self.strings.len() - 1
            }
        };
        i as f64
    }

    /// First temporary.
    pub fn temp_base(&self) -> Reg {
        self.slot_count
    }

    fn extra_base(&self) -> Reg {
        self.slot_count + MAX_TEMPS
    }

    /// The register holding a constant.
    pub fn constant(&mut self, v: f64) -> Reg {
        let key = v.to_bits();
        if let Some(r) = self.const_index.get(&key) {
            return *r;
        }
        let r = self.extra_base() + self.extra.len() as Reg;
        self.extra.push(v);
        self.const_index.insert(key, r);
        r
    }

    /// A fresh hidden register (loop limits and steps).
    pub fn hidden(&mut self) -> Reg {
        let r = self.extra_base() + self.extra.len() as Reg;
        self.extra.push(0.0);
        r
    }

    /// Initial contents of the whole value array.
    pub fn initial_values(&self, registry: &Registry) -> Vec<f64> {
        let mut v: Vec<f64> = registry.slots.iter().map(|s| s.initial).collect();
        v.resize((self.slot_count + MAX_TEMPS) as usize, 0.0);
        v.extend_from_slice(&self.extra);
        v
    }

    /// What a register is, for the disassembler.
    pub fn describe(&self, r: Reg, registry: &Registry) -> String {
        if r < self.slot_count {
            registry.slots[r as usize].name.clone()
        } else if r < self.extra_base() {
            format!("t{}", r - self.slot_count)
        } else {
            let i = (r - self.extra_base()) as usize;
            match self.extra.get(i) {
                Some(v) if self.const_index.get(&v.to_bits()) == Some(&r) => format_num(*v),
                _ => format!("h{i}"),
            }
        }
    }
}

fn format_num(v: f64) -> String {
    if v.fract() == 0.0 && v.abs() < 1e15 {
        format!("{}", v as i64)
    } else {
        format!("{v}")
    }
}

/// One compiled program.
#[derive(Debug, Clone)]
pub struct Chunk {
    /// Program number.
    pub program: u32,
    /// Source file name.
    pub file: String,
    /// The instructions.
    pub ops: Vec<Op>,
    /// Source line of each instruction.
    pub lines: Vec<u32>,
    /// The source each instruction evaluates: an operator's whole expression, a call, a
    /// statement (a store, an action, a wait).
    pub spans: Vec<Span>,
    /// The program's text, for run-time errors shown in place.
    pub source: SourceFile,
}

/// Compile a program that checked without errors.
pub fn compile(
    ast: &ProgramAst,
    src: &str,
    file: &str,
    program: u32,
    registry: &Registry,
    layout: &mut Layout,
    dialect: Dialect,
) -> Result<Chunk, Vec<Problem>> {
    let mut c = Compiler {
        registry,
        dialect,
        basic_labels: Vec::new(),
        layout,
        lines_of: LineIndex::new(src),
        ops: Vec::new(),
        lines: Vec::new(),
        spans: Vec::new(),
        line: 1,
        span: Span::new(0, 0),
        temp_top: 0,
        stmt_start: 0,
        labels: IndexMap::new(),
        gotos: Vec::new(),
        problems: Vec::new(),
    };
    if dialect == Dialect::MotionBasic {
        c.basic_labels = crate::syntax::ast::labels(&ast.body)
            .into_iter()
            .map(|seg| seg.text.to_ascii_lowercase())
            .collect();
    }
    c.block(&ast.body);
    c.emit(Op::End);
    for (at, label, span) in std::mem::take(&mut c.gotos) {
        match c.labels.get(&label) {
            Some(&target) => {
                c.ops[at] = match c.ops[at] {
                    Op::Gosub { .. } => Op::Gosub { target },
                    _ if target as usize <= at => Op::Loop { target },
                    _ => Op::Jump { target },
                };
            }
            None => c.problems.push(Problem::error(
                "pacer::check::label",
                span,
                format!("no label `{label}`"),
                "unknown label",
            )),
        }
    }
    if c.problems.is_empty() {
        Ok(Chunk {
            program,
            file: file.to_string(),
            ops: c.ops,
            lines: c.lines,
            spans: c.spans,
            source: SourceFile::new(file, src),
        })
    } else {
        Err(c.problems)
    }
}

/// Compile one expression (a line typed at the REPL) into a chunk that leaves its value in a
/// fresh hidden register of `layout`, returned with the chunk.
pub fn compile_expr(
    expr: &Expr,
    src: &str,
    file: &str,
    program: u32,
    registry: &Registry,
    layout: &mut Layout,
    dialect: Dialect,
) -> Result<(Chunk, Reg), Vec<Problem>> {
    let mut c = Compiler {
        registry,
        dialect,
        basic_labels: Vec::new(),
        layout,
        lines_of: LineIndex::new(src),
        ops: Vec::new(),
        lines: Vec::new(),
        spans: Vec::new(),
        line: 1,
        span: Span::new(0, 0),
        temp_top: 0,
        stmt_start: 0,
        labels: IndexMap::new(),
        gotos: Vec::new(),
        problems: Vec::new(),
    };
    let value = c.expr(expr);
    let dst = c.layout.hidden();
    c.emit(Op::Move { dst, src: value });
    c.emit(Op::End);
    if c.problems.is_empty() {
        let chunk = Chunk {
            program,
            file: file.to_string(),
            ops: c.ops,
            lines: c.lines,
            spans: c.spans,
            source: SourceFile::new(file, src),
        };
        Ok((chunk, dst))
    } else {
        Err(c.problems)
    }
}

/// The index of a member of the DSP axis object.
fn axis_member(name: &str) -> Option<(u8, Hook)> {
    let def = crate::registry::catalog::find_type("Axis")?;
    let i = def.members.iter().position(|m| m.name == name)?;
    Some((i as u8, def.members[i].hook))
}

struct Compiler<'a> {
    registry: &'a Registry,
    dialect: Dialect,
    basic_labels: Vec<String>,
    layout: &'a mut Layout,
    lines_of: LineIndex,
    ops: Vec<Op>,
    lines: Vec<u32>,
    spans: Vec<Span>,
    line: u32,
    /// The source span the next instructions evaluate.
    span: Span,
    temp_top: u32,
    stmt_start: usize,
    labels: IndexMap<String, u32>,
    gotos: Vec<(usize, String, Span)>,
    problems: Vec<Problem>,
}

impl Compiler<'_> {
    fn emit(&mut self, op: Op) -> usize {
        self.ops.push(op);
        self.lines.push(self.line);
        self.spans.push(self.span);
        self.ops.len() - 1
    }

    fn here(&self) -> u32 {
        self.ops.len() as u32
    }

    fn patch(&mut self, at: usize, target: u32) {
        let Some(op) = self.ops.get_mut(at) else {
            return;
        };
        match op {
            Op::Jump { target: t }
            | Op::JumpIfFalse { target: t, .. }
            | Op::JumpIfTrue { target: t, .. }
            | Op::JumpUnlessLt { target: t, .. }
            | Op::JumpUnlessLe { target: t, .. }
            | Op::JumpUnlessEq { target: t, .. }
            | Op::JumpUnlessNe { target: t, .. }
            | Op::JumpWhenLt { target: t, .. }
            | Op::JumpWhenLe { target: t, .. }
            | Op::JumpWhenEq { target: t, .. }
            | Op::JumpWhenNe { target: t, .. }
            | Op::ForCheck { exit: t, .. } => *t = target,
            _ => {}
        }
    }

    fn temp(&mut self, span: Span) -> Reg {
        if self.temp_top >= MAX_TEMPS {
            self.problems.push(Problem::error(
                "pacer::compile::too_deep",
                span,
                "expression too deeply nested",
                "simplify this expression",
            ));
            return self.layout.temp_base();
        }
        let r = self.layout.temp_base() + self.temp_top;
        self.temp_top += 1;
        r
    }

    fn block(&mut self, body: &[Stmt]) {
        for s in body {
            self.line = self.lines_of.line(s.span.start) as u32;
            self.span = s.span;
            self.temp_top = 0;
            self.stmt_start = self.ops.len();
            self.stmt(s);
        }
    }

    fn resolve(&mut self, n: &Name) -> Option<crate::registry::Resolved> {
        let r = match self.dialect {
            Dialect::PowerTools => self.registry.resolve(n),
            Dialect::MotionBasic => basic::resolve(self.registry, n),
        };
        match r {
            Ok(r) => Some(r),
            Err(p) => {
                self.problems.push(p);
                None
            }
        }
    }

    fn stmt(&mut self, s: &Stmt) {
        match &s.kind {
            StmtKind::Assign { target, value } => {
                let Some(r) = self.resolve(target) else {
                    return;
                };
                if r.access == Access::Action {
                    // `X=ON` triggers the action; `X=cond` triggers it when cond is ON.
                    match value.kind {
                        ExprKind::Bool(true) => self.act_now(&r),
                        ExprKind::Bool(false) => {}
                        _ => {
                            let skip = self.cond_jump(value);
                            self.act_now(&r);
                            let end = self.here();
                            self.patch_all(skip, end);
                        }
                    }
                    return;
                }
                let v = self.expr(value);
                self.store(&r, v);
            }
            StmtKind::Action {
                target,
                using,
                profile,
            } => {
                let Some(r) = self.resolve(target) else {
                    return;
                };
                let start = match using {
                    None => StartRef::Now,
                    Some(Using::Last(_)) => StartRef::Last,
                    Some(Using::Capture(n)) => {
                        match self.registry.resolve_instance(n, Kind::Capture) {
                            Ok(i) => StartRef::Capture(i as u16),
                            Err(p) => {
                                self.problems.push(p);
                                StartRef::Now
                            }
                        }
                    }
                };
                let profile = match profile {
                    None => 0,
                    Some(p) => match self.registry.resolve_instance(p, Kind::Profile) {
                        Ok(i) => i as u8,
                        Err(p) => {
                            self.problems.push(p);
                            0
                        }
                    },
                };
                self.emit(Op::Act {
                    hook: r.hook,
                    slot: r.slot,
                    instance: r.instance,
                    start,
                    profile,
                });
            }
            StmtKind::DwellTime(e) | StmtKind::DwellMaster(e) => {
                let src = self.expr(e);
                self.emit(Op::Dwell {
                    src,
                    master: matches!(s.kind, StmtKind::DwellMaster(_)),
                });
            }
            StmtKind::WaitTime(e) => {
                let src = self.expr(e);
                self.emit(Op::WaitTime { src });
            }
            StmtKind::WaitFor(e) => {
                let retry = self.here();
                let cond = self.expr(e);
                self.emit(Op::WaitUntil { cond, retry });
            }
            StmtKind::If {
                cond,
                then_body,
                else_body,
            } => {
                let to_else = self.cond_jump(cond);
                self.block(then_body);
                match else_body {
                    None => {
                        let end = self.here();
                        self.patch_all(to_else, end);
                    }
                    Some(else_body) => {
                        self.line = self.lines_of.line(s.span.start) as u32;
                        self.span = s.span;
                        let to_end = self.emit(Op::Jump { target: 0 });
                        let else_start = self.here();
                        self.patch_all(to_else, else_start);
                        self.block(else_body);
                        let end = self.here();
                        self.patch(to_end, end);
                    }
                }
            }
            StmtKind::DoWhile { cond, body } => {
                let top = self.here();
                let exit = self.cond_jump(cond);
                self.block(body);
                self.line = self.lines_of.line(s.span.start) as u32;
                self.span = s.span;
                self.emit(Op::Loop { target: top });
                let end = self.here();
                self.patch_all(exit, end);
            }
            StmtKind::For {
                var,
                from,
                to,
                step,
                body,
            } => {
                let Some(r) = self.resolve(var) else { return };
                let v = self.expr(from);
                self.store(&r, v);
                self.temp_top = 0;
                // The limit and the step live in two adjacent registers: step = limit + 1.
                let limit = self.layout.hidden();
                let step_reg = self.layout.hidden();
                let l = self.expr(to);
                self.emit(Op::Move { dst: limit, src: l });
                self.temp_top = 0;
                let sv = match step {
                    None => self.layout.constant(1.0),
                    Some(st) => self.expr(st),
                };
                self.emit(Op::Move {
                    dst: step_reg,
                    src: sv,
                });
                self.temp_top = 0;
                let top = self.here();
                let check = self.emit(Op::ForCheck {
                    var: r.slot,
                    limit,
                    exit: 0,
                });
                self.block(body);
                self.line = self.lines_of.line(s.span.start) as u32;
                self.span = s.span;
                self.temp_top = 0;
                let decimals = match r.ty {
                    ValueType::Fixed(d) => d,
                    ValueType::Integer => 0,
                    _ => REAL_STORE,
                };
                debug_assert_eq!(step_reg, limit + 1);
                self.emit(Op::ForNext {
                    var: r.slot,
                    limit,
                    body: top + 1,
                    decimals,
                });
                let end = self.here();
                self.patch(check, end);
            }
            StmtKind::Call(n) => match self.registry.resolve_instance(n, Kind::Program) {
                Ok(program) => {
                    self.emit(Op::CallProgram { program });
                }
                Err(p) => self.problems.push(p),
            },
            StmtKind::Label(seg) => {
                let pc = self.here();
                self.labels.insert(seg.text.to_ascii_lowercase(), pc);
            }
            StmtKind::Goto(seg) => {
                let at = self.emit(Op::Jump { target: 0 });
                self.gotos
                    .push((at, seg.text.to_ascii_lowercase(), seg.span));
            }
            StmtKind::End => {
                self.emit(Op::End);
            }
            StmtKind::Return => {
                self.emit(Op::Return);
            }
            StmtKind::Gosub(seg) => {
                let key = seg.text.to_ascii_lowercase();
                if self.basic_labels.contains(&key) {
                    let at = self.emit(Op::Gosub { target: 0 });
                    self.gotos.push((at, key, seg.span));
                } else {
                    // Not a label: an object action written bare (`Queue.0.QueueRemove`).
                    let name = Name::from_token(&seg.text, seg.span.start);
                    if let Some(r) = self.resolve(&name) {
                        self.act_now(&r);
                    }
                }
            }
            StmtKind::SetCall {
                target,
                args,
                value,
            } => {
                let Some((member, hook)) =
                    basic::controller(&target.text).and_then(|c| axis_member(c.member))
                else {
                    return;
                };
                let Some(axis) = args.first() else { return };
                let axes = self.axis_set(axis);
                let src = self.expr(value);
                self.emit(Op::AxisWrite {
                    axes,
                    src,
                    member,
                    hook,
                });
            }
            StmtKind::Gear { axis, form } => {
                let (cmd, operands, after): (MotionCmd, Vec<Option<&Expr>>, Option<&Expr>) =
                    match form {
                        GearForm::At {
                            out,
                            inn,
                            pacer,
                            after,
                        } => (
                            MotionCmd::GearAt {
                                pacer: pacer.is_some(),
                                after: after.is_some(),
                            },
                            vec![Some(out), Some(inn), pacer.as_ref()],
                            after.as_ref(),
                        ),
                        GearForm::For { dist, pacer } => {
                            (MotionCmd::GearFor, vec![Some(dist), Some(pacer)], None)
                        }
                    };
                self.motion(cmd, axis, &operands, after);
            }
            StmtKind::Move { axis, form } => {
                let (cmd, operands): (MotionCmd, Vec<Option<&Expr>>) = match form {
                    MoveForm::At { speed, time } => (
                        MotionCmd::MoveAt {
                            time: time.is_some(),
                        },
                        vec![Some(speed), time.as_ref()],
                    ),
                    MoveForm::Position {
                        relative,
                        target,
                        speed,
                        time,
                    } => (
                        MotionCmd::MovePos {
                            relative: *relative,
                            speed: speed.is_some(),
                            time: time.is_some(),
                        },
                        vec![Some(target), speed.as_ref(), time.as_ref()],
                    ),
                };
                self.motion(cmd, axis, &operands, None);
            }
        }
    }

    /// Run an action member now, on profile 0.
    fn act_now(&mut self, r: &crate::registry::Resolved) {
        self.emit(Op::Act {
            hook: r.hook,
            slot: r.slot,
            instance: r.instance,
            start: StartRef::Now,
            profile: 0,
        });
    }

    /// A motion statement: the operands go to consecutive registers (absent ones are 0), and
    /// an `AFTER` input's slot number after them.
    fn motion(
        &mut self,
        cmd: MotionCmd,
        axis: &Expr,
        operands: &[Option<&Expr>],
        after: Option<&Expr>,
    ) {
        let axes = self.axis_set(axis);
        let hold = self.temp(axis.span);
        self.emit(Op::Move {
            dst: hold,
            src: axes,
        });
        let count = operands.len() + usize::from(after.is_some());
        let regs: Vec<Reg> = (0..count).map(|_| self.temp(axis.span)).collect();
        let top = self.temp_top;
        for (e, &dst) in operands.iter().zip(&regs) {
            let src = match e {
                Some(x) => self.expr(x),
                None => self.layout.constant(0.0),
            };
            self.temp_top = top;
            self.emit(Op::Move { dst, src });
        }
        if let (Some(ExprKind::Name(n)), Some(&dst)) = (after.map(|a| &a.kind), regs.last()) {
            match self.registry.resolve(n) {
                Ok(r) => {
                    let src = self.layout.constant(f64::from(r.slot));
                    self.emit(Op::Move { dst, src });
                }
                Err(p) => self.problems.push(p),
            }
        }
        let args = regs.first().copied().unwrap_or(hold);
        self.emit(Op::Motion {
            cmd,
            axes: hold,
            args,
        });
    }

    /// An axis-set value: axis numbers become sets, sets are joined.
    fn axis_set(&mut self, e: &Expr) -> Reg {
        let outer = std::mem::replace(&mut self.span, e.span);
        let r = self.axis_set_at(e);
        self.span = outer;
        r
    }

    /// [`Compiler::axis_set`], with `e`'s span current.
    fn axis_set_at(&mut self, e: &Expr) -> Reg {
        match &e.kind {
            ExprKind::Paren(inner) => self.axis_set(inner),
            ExprKind::AxisSet(items) => {
                let mark = self.temp_top;
                let mut acc: Option<Reg> = None;
                for item in items {
                    let r = self.axis_set(item);
                    acc = Some(match acc {
                        None => r,
                        Some(prev) => {
                            let dst = self.temp(e.span);
                            self.emit(Op::Binary {
                                op: BinaryOp::BitOr,
                                dst,
                                a: prev,
                                b: r,
                            });
                            dst
                        }
                    });
                }
                let Some(r) = acc else {
                    return self.layout.constant(0.0);
                };
                self.temp_top = mark;
                let dst = self.temp(e.span);
                if r != dst {
                    self.emit(Op::Move { dst, src: r });
                }
                dst
            }
            _ if self.basic_ty(e) == BasicTy::Axis => self.expr(e),
            _ => {
                if let ExprKind::Number(n) = e.kind {
                    if n.fract() == 0.0 && (1.0..=16.0).contains(&n) {
                        return self.layout.constant(f64::from(1u32 << (n as u32 - 1)));
                    }
                }
                let mark = self.temp_top;
                let a = self.expr(e);
                self.temp_top = mark;
                let dst = self.temp(e.span);
                self.emit(Op::AxisBit { dst, a });
                dst
            }
        }
    }

    /// The MotionBASIC type of an expression (the checker has accepted it).
    fn basic_ty(&self, e: &Expr) -> BasicTy {
        match &e.kind {
            ExprKind::AxisSet(_) => BasicTy::Axis,
            ExprKind::Str(_) => BasicTy::Str,
            ExprKind::Paren(x) => self.basic_ty(x),
            ExprKind::Name(n) => match basic::resolve(self.registry, n) {
                Ok(r) if r.kind == Kind::BasicVar => {
                    basic::var_type(&r.name).map_or(BasicTy::Num, |t| t.1)
                }
                _ => BasicTy::Num,
            },
            ExprKind::Call(f, _) => basic::controller(&f.text).map_or(BasicTy::Num, |c| c.ty),
            _ => BasicTy::Num,
        }
    }

    /// True when a MotionBASIC expression is a long integer (its arithmetic overflows at 32
    /// bits, as in Microsoft BASIC).
    fn is_long(&self, e: &Expr) -> bool {
        match &e.kind {
            ExprKind::Number(v) => v.fract() == 0.0 && v.abs() <= f64::from(i32::MAX),
            ExprKind::Bool(_) => true,
            ExprKind::Paren(x) | ExprKind::Unary(UnOp::Neg, x) => self.is_long(x),
            ExprKind::Name(n) => matches!(
                basic::resolve(self.registry, n),
                Ok(r) if r.kind == Kind::BasicVar && r.ty == ValueType::Fixed(0)
            ),
            ExprKind::Binary(BinOp::IntDiv | BinOp::Mod, _, _) => true,
            ExprKind::Binary(BinOp::Add | BinOp::Sub | BinOp::Mul, a, b) => {
                self.is_long(a) && self.is_long(b)
            }
            _ => false,
        }
    }

    fn store(&mut self, r: &crate::registry::Resolved, src: Reg) {
        if self.dialect == Dialect::MotionBasic
            && r.kind == Kind::BasicVar
            && r.ty == ValueType::Fixed(0)
        {
            if let (Some(&Op::CheckLong { r: checked }), true) =
                (self.ops.last(), self.ops.len() > self.stmt_start)
            {
                if checked == src {
                    self.ops.pop();
                    self.lines.pop();
                    self.spans.pop();
                }
            }
            self.emit(Op::StoreLong { dst: r.slot, src });
            return;
        }
        // Storing into a 32-bit variable checks the range itself.
        if let (Some(&Op::CheckLong { r: checked }), ValueType::Fixed(_) | ValueType::Integer) =
            (self.ops.last(), r.ty)
        {
            if checked == src && self.ops.len() > self.stmt_start {
                self.ops.pop();
                self.lines.pop();
                self.spans.pop();
            }
        }
        if let (Hook::Store, ValueType::Fixed(_) | ValueType::Integer) = (r.hook, r.ty) {
            let decimals = if let ValueType::Fixed(d) = r.ty { d } else { 0 };
            // The value was just computed into a temporary by this statement: compute it
            // straight into the variable instead.
            if self.ops.len() > self.stmt_start {
                let fused = match self.ops.last() {
                    Some(&Op::Add { dst, a, b }) if dst == src => Some((BinaryOp::Add, a, b)),
                    Some(&Op::Sub { dst, a, b }) if dst == src => Some((BinaryOp::Sub, a, b)),
                    Some(&Op::Mul { dst, a, b }) if dst == src => Some((BinaryOp::Mul, a, b)),
                    Some(&Op::Div { dst, a, b }) if dst == src => Some((BinaryOp::Div, a, b)),
                    Some(&Op::Mod { dst, a, b }) if dst == src => Some((BinaryOp::Mod, a, b)),
                    Some(&Op::Binary { op, dst, a, b }) if dst == src => Some((op, a, b)),
                    _ => None,
                };
                if let (Some((op, a, b)), Some(last)) = (fused, self.ops.last_mut()) {
                    *last = match op {
                        BinaryOp::Add => Op::AddFixed {
                            dst: r.slot,
                            a,
                            b,
                            decimals,
                        },
                        BinaryOp::Sub => Op::SubFixed {
                            dst: r.slot,
                            a,
                            b,
                            decimals,
                        },
                        BinaryOp::Mul => Op::MulFixed {
                            dst: r.slot,
                            a,
                            b,
                            decimals,
                        },
                        _ => Op::ArithFixed {
                            op,
                            dst: r.slot,
                            a,
                            b,
                            decimals,
                        },
                    };
                    return;
                }
            }
        }
        if r.hook != Hook::Store {
            self.emit(Op::Write {
                hook: r.hook,
                slot: r.slot,
                src,
                instance: r.instance,
            });
            return;
        }
        let op = match r.ty {
            ValueType::Bit => Op::StoreBit { dst: r.slot, src },
            ValueType::Integer => Op::StoreFixed {
                dst: r.slot,
                src,
                decimals: 0,
            },
            ValueType::Fixed(d) => Op::StoreFixed {
                dst: r.slot,
                src,
                decimals: d,
            },
            ValueType::Real => Op::StoreReal { dst: r.slot, src },
        };
        self.emit(op);
    }

    /// Emit the jumps taken when `cond` is OFF; returns them, to be patched to the target.
    /// ON/OFF `AND`/`OR` short-circuit when the skipped side cannot fail (no division or MOD by
    /// a variable), which gives the same result as evaluating both sides.
    fn cond_jump(&mut self, cond: &Expr) -> Vec<usize> {
        self.jumps(cond, false)
    }

    /// Jumps taken when `cond` equals `when`.
    fn jumps(&mut self, cond: &Expr, when: bool) -> Vec<usize> {
        let outer = std::mem::replace(&mut self.span, cond.span);
        let j = self.jumps_at(cond, when);
        self.span = outer;
        j
    }

    /// [`Compiler::jumps`], with the condition's span current.
    fn jumps_at(&mut self, cond: &Expr, when: bool) -> Vec<usize> {
        match &cond.kind {
            ExprKind::Bool(b) => {
                if *b == when {
                    vec![self.emit(Op::Jump { target: 0 })]
                } else {
                    Vec::new()
                }
            }
            ExprKind::Paren(inner) => self.jumps(inner, when),
            ExprKind::Unary(UnOp::Not, inner) if self.ty(inner) == Ty::Bool => {
                self.jumps(inner, !when)
            }
            ExprKind::Binary(op @ (BinOp::And | BinOp::Or), a, b)
                if self.ty(a) == Ty::Bool && fault_free(b) =>
            {
                // AND jumps on OFF as soon as one side is OFF; OR jumps on ON as soon as one is ON.
                let short = (*op == BinOp::Or) == when;
                if short {
                    let mut j = self.jumps(a, when);
                    j.extend(self.jumps(b, when));
                    j
                } else {
                    let decided = self.jumps(a, !when);
                    let j = self.jumps(b, when);
                    let here = self.here();
                    self.patch_all(decided, here);
                    j
                }
            }
            ExprKind::Binary(op, a, b) if cmp_of(*op).is_some() => {
                let cmp = cmp_of(*op).unwrap_or(Cmp::Eq);
                let mark = self.temp_top;
                let ra = self.expr(a);
                let rb = self.expr(b);
                self.temp_top = mark;
                let op = compare_jump(cmp, ra, rb, when);
                vec![self.emit(op)]
            }
            _ => {
                let mark = self.temp_top;
                let r = self.expr(cond);
                self.temp_top = mark;
                let op = if when {
                    Op::JumpIfTrue { cond: r, target: 0 }
                } else {
                    Op::JumpIfFalse { cond: r, target: 0 }
                };
                vec![self.emit(op)]
            }
        }
    }

    fn patch_all(&mut self, jumps: Vec<usize>, target: u32) {
        for j in jumps {
            self.patch(j, target);
        }
    }

    fn ty(&self, e: &Expr) -> Ty {
        match self.dialect {
            Dialect::PowerTools => expr_type(e, self.registry).unwrap_or(Ty::Num),
            Dialect::MotionBasic => {
                if truth_valued(e) {
                    Ty::Bool
                } else {
                    Ty::Num
                }
            }
        }
    }

    /// The register holding the value of `e`; its instructions carry the span of the
    /// (sub)expression each evaluates.
    fn expr(&mut self, e: &Expr) -> Reg {
        let outer = std::mem::replace(&mut self.span, e.span);
        let r = self.expr_at(e);
        self.span = outer;
        r
    }

    /// [`Compiler::expr`], with `e`'s span current.
    fn expr_at(&mut self, e: &Expr) -> Reg {
        match &e.kind {
            ExprKind::Number(v) => self.layout.constant(*v),
            ExprKind::Bool(b) => {
                let truth = if self.dialect == Dialect::MotionBasic {
                    -1.0
                } else {
                    1.0
                };
                self.layout.constant(if *b { truth } else { 0.0 })
            }
            ExprKind::Name(n) => {
                let Some(r) = self.resolve(n) else { return 0 };
                if self.dialect == Dialect::MotionBasic && r.ty.is_bit() {
                    // MotionBASIC's true is -1.
                    let dst = self.temp(e.span);
                    self.emit(Op::Neg { dst, a: r.slot });
                    return dst;
                }
                r.slot
            }
            ExprKind::Paren(inner) => self.expr(inner),
            ExprKind::Str(text) => {
                let id = self.layout.string(text);
                self.layout.constant(id)
            }
            ExprKind::AxisSet(_) => self.axis_set(e),
            ExprKind::Unary(op, inner) => {
                let mark = self.temp_top;
                let a = self.expr(inner);
                self.temp_top = mark;
                let dst = self.temp(e.span);
                let basic = self.dialect == Dialect::MotionBasic;
                let op = match (op, self.ty(inner)) {
                    (UnOp::Neg, _) => Op::Neg { dst, a },
                    (UnOp::Not, Ty::Bool) if !basic => Op::Not { dst, a },
                    (UnOp::Not, _) => Op::BitNot { dst, a },
                };
                self.emit(op);
                if basic && matches!(e.kind, ExprKind::Unary(UnOp::Neg, _)) && self.is_long(e) {
                    self.emit(Op::CheckLong { r: dst });
                }
                dst
            }
            ExprKind::Binary(op, l, r) => {
                let mark = self.temp_top;
                let a = self.expr(l);
                let b = self.expr(r);
                self.temp_top = mark;
                let dst = self.temp(e.span);
                let basic = self.dialect == Dialect::MotionBasic;
                // MotionBASIC's AND/OR/XOR are bitwise on integers (true is -1).
                let boolean = !basic && self.ty(l) == Ty::Bool;
                let binop = *op;
                let op = match op {
                    BinOp::IntDiv => Op::Binary {
                        op: BinaryOp::IntDiv,
                        dst,
                        a,
                        b,
                    },
                    BinOp::Add => Op::Add { dst, a, b },
                    BinOp::Sub => Op::Sub { dst, a, b },
                    BinOp::Mul => Op::Mul { dst, a, b },
                    BinOp::Div => Op::Div { dst, a, b },
                    BinOp::Mod if basic => Op::Binary {
                        op: BinaryOp::BasicMod,
                        dst,
                        a,
                        b,
                    },
                    BinOp::Mod => Op::Mod { dst, a, b },
                    BinOp::Pow => Op::Binary {
                        op: BinaryOp::Pow,
                        dst,
                        a,
                        b,
                    },
                    BinOp::And => Op::Binary {
                        op: if boolean {
                            BinaryOp::And
                        } else {
                            BinaryOp::BitAnd
                        },
                        dst,
                        a,
                        b,
                    },
                    BinOp::Or => Op::Binary {
                        op: if boolean {
                            BinaryOp::Or
                        } else {
                            BinaryOp::BitOr
                        },
                        dst,
                        a,
                        b,
                    },
                    BinOp::Xor => Op::Binary {
                        op: if boolean {
                            BinaryOp::Xor
                        } else {
                            BinaryOp::BitXor
                        },
                        dst,
                        a,
                        b,
                    },
                    cmp => Op::Compare {
                        cmp: cmp_of(*cmp).unwrap_or(Cmp::Eq),
                        dst,
                        a,
                        b,
                    },
                };
                self.emit(op);
                if basic {
                    if cmp_of(binop).is_some() {
                        self.emit(Op::Neg { dst, a: dst });
                    } else if matches!(binop, BinOp::Add | BinOp::Sub | BinOp::Mul)
                        && self.is_long(e)
                    {
                        self.emit(Op::CheckLong { r: dst });
                    }
                }
                dst
            }
            ExprKind::Call(f, args)
                if self.dialect == Dialect::MotionBasic && basic::controller(&f.text).is_some() =>
            {
                let Some((member, _)) =
                    basic::controller(&f.text).and_then(|c| axis_member(c.member))
                else {
                    return 0;
                };
                let mark = self.temp_top;
                let axes = match args.first() {
                    Some(a) => self.axis_set(a),
                    None => self.layout.constant(0.0),
                };
                self.temp_top = mark;
                let dst = self.temp(e.span);
                let truth = self.registry.of(Kind::Axis).def.members[member as usize]
                    .ty
                    .is_bit();
                self.emit(Op::AxisRead {
                    dst,
                    axes,
                    member,
                    truth,
                });
                dst
            }
            ExprKind::Call(f, args) if functions::find_kernel(&f.text).is_some() => {
                let Some((func, _)) = functions::find_kernel(&f.text) else {
                    return 0;
                };
                let mark = self.temp_top;
                let regs: Vec<Reg> = args.iter().map(|_| self.temp(e.span)).collect();
                let top = self.temp_top;
                for (a, &dst) in args.iter().zip(&regs) {
                    let src = self.expr(a);
                    self.temp_top = top;
                    self.emit(Op::Move { dst, src });
                }
                self.temp_top = mark;
                let dst = self.temp(e.span);
                let args = regs.first().copied().unwrap_or(dst);
                self.emit(Op::KernelCall { func, dst, args });
                // REGIST's and WRITE_SV's OK is a truth value: -1 in MotionBASIC.
                if self.dialect == Dialect::MotionBasic
                    && matches!(
                        func,
                        functions::KernelFunc::Regist | functions::KernelFunc::WriteSv
                    )
                {
                    self.emit(Op::Neg { dst, a: dst });
                }
                dst
            }
            ExprKind::Call(f, args) => {
                let Some((func, _)) = functions::find(&f.text) else {
                    return 0;
                };
                let mark = self.temp_top;
                let a = args.first().map_or(0, |x| self.expr(x));
                let b = args.get(1).map_or(a, |x| self.expr(x));
                self.temp_top = mark;
                let dst = self.temp(e.span);
                self.emit(Op::Call { func, dst, a, b });
                dst
            }
        }
    }
}

/// A conditional jump on a comparison; `>` and `>=` become `<` and `<=` with the operands
/// swapped (the same answer, NaN included), so only four comparisons need their own ops.
fn compare_jump(cmp: Cmp, a: Reg, b: Reg, when: bool) -> Op {
    let target = 0;
    match (cmp, when) {
        (Cmp::Lt, false) => Op::JumpUnlessLt { a, b, target },
        (Cmp::Gt, false) => Op::JumpUnlessLt { a: b, b: a, target },
        (Cmp::Le, false) => Op::JumpUnlessLe { a, b, target },
        (Cmp::Ge, false) => Op::JumpUnlessLe { a: b, b: a, target },
        (Cmp::Eq, false) => Op::JumpUnlessEq { a, b, target },
        (Cmp::Ne, false) => Op::JumpUnlessNe { a, b, target },
        (Cmp::Lt, true) => Op::JumpWhenLt { a, b, target },
        (Cmp::Gt, true) => Op::JumpWhenLt { a: b, b: a, target },
        (Cmp::Le, true) => Op::JumpWhenLe { a, b, target },
        (Cmp::Ge, true) => Op::JumpWhenLe { a: b, b: a, target },
        (Cmp::Eq, true) => Op::JumpWhenEq { a, b, target },
        (Cmp::Ne, true) => Op::JumpWhenNe { a, b, target },
    }
}

/// True when evaluating `e` can never fail at run time (division and MOD by a variable can).
fn fault_free(e: &Expr) -> bool {
    match &e.kind {
        ExprKind::Number(_) | ExprKind::Bool(_) | ExprKind::Name(_) => true,
        ExprKind::Paren(x) | ExprKind::Unary(_, x) => fault_free(x),
        ExprKind::Binary(BinOp::Div | BinOp::Mod, a, b) => {
            fault_free(a) && matches!(b.kind, ExprKind::Number(v) if v != 0.0)
        }
        ExprKind::Binary(_, a, b) => fault_free(a) && fault_free(b),
        // Kernel functions and controller variables can fail (a wrong axis) or act.
        ExprKind::Call(f, args) => {
            functions::find(&f.text).is_some() && args.iter().all(fault_free)
        }
        ExprKind::AxisSet(args) => args.iter().all(fault_free),
        ExprKind::Str(_) => true,
    }
}

/// A MotionBASIC expression whose value is a truth value (-1 or 0), so a condition on it may
/// short-circuit: comparisons, TRUE/FALSE, and NOT/AND/OR of truth values.
fn truth_valued(e: &Expr) -> bool {
    match &e.kind {
        ExprKind::Bool(_) => true,
        ExprKind::Paren(x) | ExprKind::Unary(UnOp::Not, x) => truth_valued(x),
        ExprKind::Binary(op, a, b) => {
            cmp_of(*op).is_some()
                || (matches!(op, BinOp::And | BinOp::Or | BinOp::Xor)
                    && truth_valued(a)
                    && truth_valued(b))
        }
        _ => false,
    }
}

fn cmp_of(op: BinOp) -> Option<Cmp> {
    Some(match op {
        BinOp::Eq => Cmp::Eq,
        BinOp::Ne => Cmp::Ne,
        BinOp::Lt => Cmp::Lt,
        BinOp::Le => Cmp::Le,
        BinOp::Gt => Cmp::Gt,
        BinOp::Ge => Cmp::Ge,
        _ => return None,
    })
}
