//! The compiler: a checked program's AST to bytecode, names resolved to slots.

pub mod bytecode;
pub mod disasm;

use crate::check::{expr_type, functions, Ty};
use crate::diag::Problem;
use crate::registry::{Access, Hook, Kind, Registry, ValueType};
use crate::syntax::ast::{BinOp, Expr, ExprKind, Name, ProgramAst, Stmt, StmtKind, UnOp, Using};
use crate::syntax::span::{LineIndex, Span};
use bytecode::{BinaryOp, Cmp, Op, Reg, StartRef, REAL_STORE};
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
}

impl Layout {
    /// A layout after the registry's slots.
    pub fn new(registry: &Registry) -> Layout {
        Layout {
            slot_count: registry.slot_count() as u32,
            extra: Vec::new(),
            const_index: BTreeMap::new(),
        }
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
}

/// Compile a program that checked without errors.
pub fn compile(
    ast: &ProgramAst,
    src: &str,
    file: &str,
    program: u32,
    registry: &Registry,
    layout: &mut Layout,
) -> Result<Chunk, Vec<Problem>> {
    let mut c = Compiler {
        registry,
        layout,
        lines_of: LineIndex::new(src),
        ops: Vec::new(),
        lines: Vec::new(),
        line: 1,
        temp_top: 0,
        stmt_start: 0,
        labels: IndexMap::new(),
        gotos: Vec::new(),
        problems: Vec::new(),
    };
    c.block(&ast.body);
    c.emit(Op::End);
    for (at, label, span) in std::mem::take(&mut c.gotos) {
        match c.labels.get(&label) {
            Some(&target) => {
                c.ops[at] = if target as usize <= at {
                    Op::Loop { target }
                } else {
                    Op::Jump { target }
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
        })
    } else {
        Err(c.problems)
    }
}

struct Compiler<'a> {
    registry: &'a Registry,
    layout: &'a mut Layout,
    lines_of: LineIndex,
    ops: Vec<Op>,
    lines: Vec<u32>,
    line: u32,
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
            self.temp_top = 0;
            self.stmt_start = self.ops.len();
            self.stmt(s);
        }
    }

    fn resolve(&mut self, n: &Name) -> Option<crate::registry::Resolved> {
        match self.registry.resolve(n) {
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
                        ExprKind::Bool(true) => {
                            self.emit(Op::Act {
                                hook: r.hook,
                                slot: r.slot,
                                instance: r.instance,
                                start: StartRef::Now,
                                profile: 0,
                            });
                        }
                        ExprKind::Bool(false) => {}
                        _ => {
                            let skip = self.cond_jump(value);
                            self.emit(Op::Act {
                                hook: r.hook,
                                slot: r.slot,
                                instance: r.instance,
                                start: StartRef::Now,
                                profile: 0,
                            });
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
        }
    }

    fn store(&mut self, r: &crate::registry::Resolved, src: Reg) {
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
        expr_type(e, self.registry).unwrap_or(Ty::Num)
    }

    fn expr(&mut self, e: &Expr) -> Reg {
        match &e.kind {
            ExprKind::Number(v) => self.layout.constant(*v),
            ExprKind::Bool(b) => self.layout.constant(if *b { 1.0 } else { 0.0 }),
            ExprKind::Name(n) => self.resolve(n).map_or(0, |r| r.slot),
            ExprKind::Paren(inner) => self.expr(inner),
            ExprKind::Unary(op, inner) => {
                let mark = self.temp_top;
                let a = self.expr(inner);
                self.temp_top = mark;
                let dst = self.temp(e.span);
                let op = match (op, self.ty(inner)) {
                    (UnOp::Neg, _) => Op::Neg { dst, a },
                    (UnOp::Not, Ty::Bool) => Op::Not { dst, a },
                    (UnOp::Not, Ty::Num) => Op::BitNot { dst, a },
                };
                self.emit(op);
                dst
            }
            ExprKind::Binary(op, l, r) => {
                let mark = self.temp_top;
                let a = self.expr(l);
                let b = self.expr(r);
                self.temp_top = mark;
                let dst = self.temp(e.span);
                let boolean = self.ty(l) == Ty::Bool;
                let op = match op {
                    BinOp::Add => Op::Add { dst, a, b },
                    BinOp::Sub => Op::Sub { dst, a, b },
                    BinOp::Mul => Op::Mul { dst, a, b },
                    BinOp::Div => Op::Div { dst, a, b },
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
        ExprKind::Call(_, args) => args.iter().all(fault_free),
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
