//! The compiler: a checked, typed program to bytecode. Names are already slots and every
//! operator already has its dialect's meaning; the compiler only chooses instructions (fused
//! arithmetic stores, compare-and-jump, short-circuit conditions where they cannot change the
//! outcome) and lays out the registers.

pub mod body;
pub mod bytecode;
pub mod disasm;
pub mod tight;
pub mod whole;

use crate::check::functions::Func;
use crate::check::typed::{
    Element, Expr, ExprKind, Op as TypedOp, Place, PrintItem, Program, Stmt, StmtKind, Ty,
};
use crate::devices::command::MotionCmd;
use crate::diag::{Problem, SourceFile};
use crate::registry::{Hook, Kind, Registry, Resolved, ValueType};
use crate::span::{LineIndex, Span};
use bytecode::{BinaryOp, Cmp, DataConst, ExtOp, Op, Reg, StartRef, INT_STORE, REAL_STORE};
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
    /// The string table's initial contents (MotionBASIC): a string value is an index here.
    /// Index 0 is the empty string (a string variable never assigned); then the literals and
    /// the cells of string variables and string-making instructions, which the run changes.
    pub strings: Vec<String>,
    /// The string variables' and string array elements' slots, each with its own cell.
    text_slots: Vec<(Reg, u32)>,
    /// The literals' indices, by text.
    literal_index: BTreeMap<String, u32>,
    /// Per registry slot: a variable every store rounds to a whole number within 32 bits (a
    /// MotionBASIC long or INTEGER, a PowerTools variable without decimals).
    whole_slots: Vec<bool>,
}

/// Whether a MotionBASIC variable or array element of this registry name is an INTEGER (`%`,
/// 16 bits).
pub fn is_int16_name(name: &str) -> bool {
    name.split('(')
        .next()
        .is_some_and(|base| base.ends_with('%'))
}

pub use crate::registry::slot_name::is_text_name;

impl Layout {
    /// A layout after the registry's slots; every string variable gets its cell.
    pub fn new(registry: &Registry) -> Layout {
        let mut layout = Layout {
            slot_count: registry.slot_count() as u32,
            extra: Vec::new(),
            const_index: BTreeMap::new(),
            strings: vec![String::new()],
            text_slots: Vec::new(),
            literal_index: BTreeMap::new(),
            // A spare slot the REPL may later give any type is left out.
            whole_slots: registry
                .slots
                .iter()
                .map(|info| {
                    matches!(info.kind, Kind::Var | Kind::BasicVar)
                        && matches!(info.ty, ValueType::Fixed(0) | ValueType::Integer)
                        && !info.name.starts_with(crate::vm::live::SPARE_VARIABLE)
                        && !info.name.is_text()
                })
                .collect(),
        };
        for (i, info) in registry.slots.iter().enumerate() {
            if info.kind == Kind::BasicVar && info.name.is_text() {
                let cell = layout.cell();
                layout.text_slots.push((i as Reg, cell));
            }
        }
        layout
    }

    /// The value standing for a string literal.
    pub fn string(&mut self, s: &str) -> f64 {
        if let Some(&i) = self.literal_index.get(s) {
            return f64::from(i);
        }
        let i = self.cell();
        self.strings[i as usize] = s.to_string();
        self.literal_index.insert(s.to_string(), i);
        f64::from(i)
    }

    /// A new cell of the string table, empty at the start of a run.
    pub fn cell(&mut self) -> u32 {
        self.strings.push(String::new());
        (self.strings.len() - 1) as u32
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

    /// Whether register `r` always holds a whole number within 32 bits, never -0: a variable
    /// of [`Layout::whole_slots`] (every store makes a zero +0), or a constant that is one
    /// (constants are never written).
    pub fn is_whole(&self, r: Reg) -> bool {
        if r < self.slot_count {
            return self.whole_slots.get(r as usize).copied().unwrap_or(false);
        }
        let Some(v) = self.constant_value(r) else {
            return false;
        };
        // A -0 is left out: a sure variable or constant is never -0 (`whole::PLAIN`).
        f64::from(crate::fixed::trunc_i32(v)) == v && v.to_bits() != (-0.0f64).to_bits()
    }

    /// The value of register `r` when it is a constant ([`Layout::constant`]): never written.
    pub fn constant_value(&self, r: Reg) -> Option<f64> {
        let &v = r
            .checked_sub(self.extra_base())
            .and_then(|k| self.extra.get(k as usize))?;
        (self.const_index.get(&v.to_bits()) == Some(&r)).then_some(v)
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
        for &(slot, cell) in &self.text_slots {
            if let Some(x) = v.get_mut(slot as usize) {
                *x = f64::from(cell);
            }
        }
        v.resize((self.slot_count + MAX_TEMPS) as usize, 0.0);
        v.extend_from_slice(&self.extra);
        v
    }

    /// What a register is, for the disassembler.
    pub fn describe(&self, r: Reg, registry: &Registry) -> String {
        if r < self.slot_count {
            registry.slots[r as usize].name.to_string()
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
    /// Per instruction, what the compiler knows of its operands ([`whole::SURE`],
    /// [`whole::WIDE`], [`whole::PLAIN`]: whole numbers, within 32 bits or not, never -0),
    /// which the interpreter then takes without testing ([`whole`]).
    pub sure: Vec<u8>,
    /// One past the largest register the interpreter's loop uses unchecked
    /// ([`Op::max_register`]): the value array must be at least this long.
    pub regs_end: usize,
    /// The chunk ends with `End`, every jump stays inside it and every instruction has its
    /// [`Chunk::sure`] flag, so the interpreter fetches instructions and flags without a bounds
    /// check (it refuses a chunk that is not closed).
    pub closed: bool,
    /// Source line of each instruction.
    pub lines: Vec<u32>,
    /// The source each instruction evaluates: an operator's whole expression, a call, a
    /// statement (a store, an action, a wait).
    pub spans: Vec<Span>,
    /// The program's text, for run-time errors shown in place.
    pub source: SourceFile,
    /// The instructions [`Op::Ext`] names.
    pub ext: Vec<ExtOp>,
    /// The terms of the chunk's sums ([`Op::SumReal`]).
    pub terms: Vec<bytecode::Term>,
    /// The program's `DATA` constants, in program order.
    pub data: Vec<DataConst>,
    /// The loops the machine may run outside the interpreter on typed registers
    /// ([`body::Body`]), by the instruction their body starts at.
    pub bodies: BTreeMap<u32, body::Body>,
    /// Where the machine may go on running a loop of [`Chunk::bodies`] at the start of a turn
    /// (`body::heads`): by instruction, the loop's entering instruction and its body's
    /// instruction.
    pub heads: BTreeMap<u32, (u32, u16)>,
    /// The instructions before fusion, as the translation of bodies reads them
    /// ([`link_calls`]).
    pub plain: Plain,
}

/// A program's instructions before fusion, with the side table before it is specialized and
/// their `whole` flags: what [`body::find`] reads.
#[derive(Debug, Clone, Default)]
pub struct Plain {
    /// The instructions.
    pub ops: Vec<Op>,
    /// The side table.
    pub ext: Vec<ExtOp>,
    /// The flags, one per instruction.
    pub sure: Vec<u8>,
}

impl Plain {
    /// The instructions as [`body::find`] takes them.
    pub fn code(&self) -> body::Unfused<'_> {
        body::Unfused {
            ops: &self.ops,
            ext: &self.ext,
            sure: &self.sure,
        }
    }
}

/// Once every program of a machine is compiled (`programs`: each one's chunk, by number):
/// the loops that call other programs (`Call Program`) whose bodies, those programs run
/// inside them, the machine may run outside the interpreter ([`body::find`]), added to
/// their chunks' [`Chunk::bodies`]. A loop holding a loop `vm::tight` runs stays with the
/// interpreter, as [`compile`] leaves it.
pub fn link_calls(chunks: &mut [Chunk], programs: &IndexMap<u32, usize>, layout: &Layout) {
    let temps = layout.temp_base()..layout.temp_base() + MAX_TEMPS;
    for k in 0..chunks.len() {
        let calls = chunks[k]
            .plain
            .ops
            .iter()
            .any(|op| matches!(op, Op::CallProgram { .. }));
        if !calls {
            continue;
        }
        let found = {
            let all = &*chunks;
            // A program calling itself is the interpreter's fault to report.
            let called = |program: u32| {
                let &c = programs.get(&program).filter(|&&c| c != k)?;
                let callee = all.get(c).filter(|c| c.closed)?;
                Some((c, callee.plain.code()))
            };
            body::find(
                all[k].plain.code(),
                &called,
                &temps,
                &|r| layout.is_whole(r),
                &|r| layout.constant_value(r),
            )
        };
        let chunk = &mut chunks[k];
        let tight = |ops: &[Op], bodies: &BTreeMap<u32, body::Body>, b: &body::Body| {
            (b.start..b.after).any(|i| {
                matches!(ops.get(i as usize), Some(Op::ForTight { .. })) && !bodies.contains_key(&i)
            })
        };
        let mut added = BTreeMap::new();
        for (entry, b) in found {
            let calls = b.subs.iter().any(|s| s.call.is_some());
            if calls && !chunk.bodies.contains_key(&entry) && !tight(&chunk.ops, &chunk.bodies, &b)
            {
                added.insert(entry, b);
            }
        }
        if added.is_empty() {
            continue;
        }
        chunk.bodies.append(&mut added);
        body::mark(&mut chunk.ops, &chunk.bodies);
        chunk.heads = body::heads(&chunk.bodies);
    }
}

/// Compile a program that checked without errors. `src` and `file` are its text and name
/// (run-time errors are shown in them).
pub fn compile(
    program: &Program,
    src: &str,
    file: &str,
    number: u32,
    layout: &mut Layout,
) -> Result<Chunk, Vec<Problem>> {
    let mut c = Compiler::new(layout, src);
    c.block(&program.body);
    c.emit(Op::End);
    for (at, label) in std::mem::take(&mut c.gotos) {
        // The checker has checked every label.
        let Some(&target) = c.labels.get(&label) else {
            continue;
        };
        c.ops[at] = match c.ops[at] {
            Op::Gosub { .. } => Op::Gosub { target },
            _ if target as usize <= at => Op::Loop { target },
            _ => Op::Jump { target },
        };
    }
    for (at, label) in std::mem::take(&mut c.restores) {
        let item = c.label_data.get(&label).copied().unwrap_or(0);
        if let Some(op) = c.ext.get_mut(at) {
            *op = ExtOp::Restore { item };
        }
    }
    c.finish(number, file, src)
}

/// Compile one expression (a line typed at the REPL) into a chunk that leaves its value in a
/// fresh hidden register of `layout`, returned with the chunk.
pub fn compile_expr(
    expr: &Expr,
    src: &str,
    file: &str,
    number: u32,
    layout: &mut Layout,
) -> Result<(Chunk, Reg), Vec<Problem>> {
    let mut c = Compiler::new(layout, src);
    let value = c.expr(expr);
    let dst = c.layout.hidden();
    c.emit(Op::Move { dst, src: value });
    c.emit(Op::End);
    c.finish(number, file, src).map(|chunk| (chunk, dst))
}

struct Compiler<'a> {
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
    gotos: Vec<(usize, String)>,
    problems: Vec<Problem>,
    ext: Vec<ExtOp>,
    data: Vec<DataConst>,
    /// Per label, the number of DATA constants before it (where `RESTORE label` goes).
    label_data: IndexMap<String, u32>,
    /// `RESTORE label` instructions to patch: the index in `ext`, the label.
    restores: Vec<(usize, String)>,
}

impl<'a> Compiler<'a> {
    fn new(layout: &'a mut Layout, src: &str) -> Compiler<'a> {
        Compiler {
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
            ext: Vec::new(),
            data: Vec::new(),
            label_data: IndexMap::new(),
            restores: Vec::new(),
        }
    }

    fn finish(mut self, program: u32, file: &str, src: &str) -> Result<Chunk, Vec<Problem>> {
        if !self.problems.is_empty() {
            return Err(self.problems);
        }
        let temps = self.layout.temp_base()..self.layout.temp_base() + MAX_TEMPS;
        let sure = whole::operands(&self.ops, &temps, &|r| self.layout.is_whole(r));
        // The programs a loop calls are translated with it once they are all compiled
        // (`link_calls`), from the instructions kept as they are now.
        let plain = Plain {
            ops: self.ops.clone(),
            ext: self.ext.clone(),
            sure: sure.clone(),
        };
        let mut bodies = body::find(
            plain.code(),
            &|_| None,
            &temps,
            &|r| self.layout.is_whole(r),
            &|r| self.layout.constant_value(r),
        );
        let mut terms = Vec::new();
        let layout = &mut *self.layout;
        bytecode::fuse_sums(
            &mut self.ops,
            &temps,
            &mut || layout.constant(1.0),
            &mut terms,
        );
        bytecode::fuse(&mut self.ops, temps.clone());
        bytecode::fuse_with_constants(&mut self.ops, &temps, &|r| self.layout.constant_value(r));
        bytecode::fuse_text(&mut self.ops, &self.ext, &temps);
        bytecode::fuse_ext_pairs(&mut self.ops);
        bytecode::specialize_text(&mut self.ext);
        let sure = whole::per_instruction(&self.ops, &sure);
        tight::mark(&mut self.ops, &sure);
        // A loop `vm::tight` runs (one store an iteration: a fill, a sieve's marking) goes
        // faster there than as a part of a body holding it (bench/array took 1.13 times the
        // instructions so, its sieve about 1.6): such a body stays with the interpreter, which
        // hands that loop over.
        bodies.retain(|_, b| {
            !(b.start..b.after)
                .any(|i| matches!(self.ops.get(i as usize), Some(Op::ForTight { .. })))
        });
        body::mark(&mut self.ops, &bodies);
        let heads = body::heads(&bodies);
        let regs_end = self
            .ops
            .iter()
            .filter_map(Op::max_register)
            .chain(terms.iter().map(|t| t.a.max(t.b)))
            .map(|r| r as usize + 1)
            .max()
            .unwrap_or(0);
        // Every instruction the interpreter can reach is inside the chunk: it ends with `End`
        // (so running on from any other instruction stays inside), and every target is inside;
        // each has its flag.
        let len = self.ops.len();
        let closed = matches!(self.ops.last(), Some(Op::End))
            && sure.len() == len
            && self
                .ops
                .iter()
                .all(|op| op.target().is_none_or(|t| (t as usize) < len));
        Ok(Chunk {
            regs_end,
            closed,
            program,
            file: file.to_string(),
            ops: self.ops,
            sure,
            lines: self.lines,
            spans: self.spans,
            source: SourceFile::new(file, src),
            ext: self.ext,
            terms,
            data: self.data,
            bodies,
            heads,
            plain,
        })
    }

    /// Emit an [`Op::Ext`] instruction; its index in the side table.
    fn emit_ext(&mut self, op: ExtOp) -> usize {
        self.emit_ext_counting(op, 0)
    }

    /// [`Compiler::emit_ext`] of an instruction counting as `1 + copies` ([`Op::Ext`]).
    fn emit_ext_counting(&mut self, op: ExtOp, copies: u8) -> usize {
        self.ext.push(op);
        let at = self.ext.len() - 1;
        self.emit(Op::Ext {
            at: at as u32,
            copies,
        });
        at
    }

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

    /// The instructions of a statement's line and span from here on.
    fn at_statement(&mut self, s: &Stmt) {
        self.line = self.lines_of.line(s.span.start) as u32;
        self.span = s.span;
    }

    /// `ON n GOTO`/`ON n GOSUB` (its `IF`s, `on_cases`): `CINT(n)` computed once into a
    /// temporary, then compared with 1, 2, … — not once per case, which would draw a new `RND`
    /// at each (a uniform pick of three came out 1/3, 2/9, 4/27…) and cost a call per case.
    fn on_jump(&mut self, s: &Stmt, selector: &Expr, cases: &[&[Stmt]]) {
        let outer = std::mem::replace(&mut self.span, selector.span);
        let mark = self.temp_top;
        let picked = self.expr(selector);
        self.span = outer;
        let mut to_end = Vec::new();
        for (k, body) in cases.iter().enumerate() {
            self.span = selector.span;
            let case = self.layout.constant((k + 1) as f64);
            let skip = self.emit(compare_jump(Cmp::Eq, picked, case, false));
            self.span = outer;
            // The cases are one GOSUB or GOTO each (`on_cases`): they take no temporary, so
            // none meets `picked`.
            self.block(body);
            if k + 1 < cases.len() {
                self.at_statement(s);
                to_end.push(self.emit(Op::Jump { target: 0 }));
            }
            let next = self.here();
            self.patch(skip, next);
        }
        let end = self.here();
        self.patch_all(to_end, end);
        self.temp_top = mark;
    }

    /// `IF cond THEN then_body [ELSE else_body]`.
    fn if_else(&mut self, s: &Stmt, cond: &Expr, then_body: &[Stmt], else_body: Option<&[Stmt]>) {
        let to_else = self.cond_jump(cond);
        self.block(then_body);
        match else_body {
            None => {
                let end = self.here();
                self.patch_all(to_else, end);
            }
            Some(else_body) => {
                self.at_statement(s);
                let to_end = self.emit(Op::Jump { target: 0 });
                let else_start = self.here();
                self.patch_all(to_else, else_start);
                self.block(else_body);
                let end = self.here();
                self.patch(to_end, end);
            }
        }
    }

    fn block(&mut self, body: &[Stmt]) {
        for s in body {
            self.at_statement(s);
            self.temp_top = 0;
            self.stmt_start = self.ops.len();
            self.stmt(s);
        }
    }

    fn stmt(&mut self, s: &Stmt) {
        match &s.kind {
            StmtKind::Assign { target, value } if value.ty == Ty::Str => {
                let src = self.expr(value);
                self.emit_ext(ExtOp::StoreText {
                    dst: target.slot,
                    src,
                });
            }
            StmtKind::Assign { target, value } => {
                let v = self.expr(value);
                self.store(target, v);
            }
            StmtKind::SetElement { place, value } => {
                let src = self.expr(value);
                self.set_element(place, src);
            }
            StmtKind::Data(items) => {
                for item in items {
                    let text = self.layout.string(&item.text) as u32;
                    let line = self.lines_of.line(item.span.start) as u32;
                    self.data.push(DataConst {
                        number: item.number,
                        text,
                        written: item.text.clone(),
                        line,
                    });
                }
            }
            StmtKind::Read(places) => {
                for place in places {
                    self.temp_top = 0;
                    let dst = self.temp(s.span);
                    let text = place_is_text(place);
                    self.emit_ext(ExtOp::Read { dst, text });
                    self.store_place(place, dst);
                }
            }
            StmtKind::Restore(label) => {
                let at = self.emit_ext(ExtOp::Restore { item: 0 });
                if let Some(key) = label {
                    self.restores.push((at, key.clone()));
                }
            }
            StmtKind::Swap(a, b) => self.swap(a, b),
            StmtKind::MidSet {
                place,
                start,
                count,
                value,
            } => self.mid_set(place, start, count.as_ref(), value),
            StmtKind::Randomize(seed) => {
                let seed = seed.as_ref().map(|e| self.expr(e));
                self.emit_ext(ExtOp::Randomize { seed });
            }
            StmtKind::Act {
                target,
                start,
                profile,
                when,
            } => match when {
                None => self.act(target, *start, *profile),
                // `X=cond` triggers the action when cond is ON.
                Some(cond) => {
                    let skip = self.cond_jump(cond);
                    self.act(target, *start, *profile);
                    let end = self.here();
                    self.patch_all(skip, end);
                }
            },
            StmtKind::Nothing => {}
            StmtKind::Dwell {
                length,
                domain,
                last,
            } => {
                let src = self.expr(length);
                self.emit(Op::Dwell {
                    src,
                    master: *domain == crate::devices::command::Domain::Master,
                    last: *last,
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
            } => match on_cases(&s.kind) {
                Some((selector, cases)) => self.on_jump(s, selector, &cases),
                None => self.if_else(s, cond, then_body, else_body.as_deref()),
            },
            StmtKind::While { cond, body } => {
                let top = self.here();
                let exit = self.cond_jump(cond);
                self.block(body);
                self.at_statement(s);
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
                let v = self.expr(from);
                self.store(var, v);
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
                    var: var.slot,
                    limit,
                    exit: 0,
                });
                self.block(body);
                self.at_statement(s);
                self.temp_top = 0;
                let decimals = match var.ty {
                    _ if var.kind == Kind::BasicVar && is_int16_name(&var.name) => INT_STORE,
                    ValueType::Fixed(d) => d,
                    ValueType::Integer => 0,
                    _ => REAL_STORE,
                };
                debug_assert_eq!(step_reg, limit + 1);
                self.emit(Op::ForNext {
                    var: var.slot,
                    limit,
                    body: top + 1,
                    decimals,
                });
                let end = self.here();
                self.patch(check, end);
            }
            StmtKind::Call(program) => {
                self.emit(Op::CallProgram { program: *program });
            }
            StmtKind::Label(key) => {
                let pc = self.here();
                self.labels.insert(key.clone(), pc);
                self.label_data.insert(key.clone(), self.data.len() as u32);
            }
            StmtKind::Goto(key) => {
                let at = self.emit(Op::Jump { target: 0 });
                self.gotos.push((at, key.clone()));
            }
            StmtKind::Print(items) => {
                for item in items {
                    self.temp_top = 0;
                    match item {
                        PrintItem::Value(e, how) => {
                            let src = self.expr(e);
                            self.emit(Op::Print { src, how: *how });
                        }
                        PrintItem::Comma => {
                            self.emit(Op::PrintZone);
                        }
                        PrintItem::Semicolon => {}
                    }
                }
                if !matches!(items.last(), Some(PrintItem::Comma | PrintItem::Semicolon)) {
                    self.emit(Op::PrintLine);
                }
            }
            StmtKind::PrintUsing {
                format,
                values,
                newline,
            } => {
                let regs: Vec<Reg> = values.iter().map(|_| self.temp(s.span)).collect();
                let fmt = self.temp(s.span);
                let top = self.temp_top;
                let src = self.expr(format);
                self.emit(Op::Move { dst: fmt, src });
                self.temp_top = top;
                for (e, &dst) in values.iter().zip(&regs) {
                    let src = self.expr(e);
                    self.temp_top = top;
                    self.emit(Op::Move { dst, src });
                }
                let texts = values
                    .iter()
                    .enumerate()
                    .filter(|(_, e)| e.ty == Ty::Str)
                    .fold(0u64, |m, (i, _)| m | (1 << i));
                self.emit_ext(ExtOp::PrintUsing {
                    format: fmt,
                    args: regs.first().copied().unwrap_or(fmt),
                    count: values.len() as u32,
                    texts,
                });
                if *newline {
                    self.emit(Op::PrintLine);
                }
            }
            StmtKind::Gosub(key) => {
                let at = self.emit(Op::Gosub { target: 0 });
                self.gotos.push((at, key.clone()));
            }
            StmtKind::End => {
                self.emit(Op::End);
            }
            StmtKind::Return => {
                self.emit(Op::Return);
            }
            StmtKind::AxisWrite {
                member,
                hook,
                axes,
                value,
            } => {
                let axes = self.axis_set(axes);
                let src = self.expr(value);
                self.emit(Op::AxisWrite {
                    axes,
                    src,
                    member: *member,
                    hook: *hook,
                    text: value.ty == Ty::Str,
                });
            }
            StmtKind::Motion {
                cmd,
                axes,
                operands,
                after,
            } => self.motion(*cmd, axes, operands, *after),
        }
    }

    /// The register holding an element's offset from its array's first element: each
    /// subscript checked against its bound, row-major (the last subscript varies fastest).
    fn offset(&mut self, el: &Element) -> Reg {
        let mut acc: Option<Reg> = None;
        for (sub, &bound) in el.subs.iter().zip(&el.bounds) {
            let len = bound + 1;
            let mark = self.temp_top;
            let src = self.expr(sub);
            self.check_subscript(el, sub, src, bound);
            self.temp_top = mark;
            let s = self.temp(sub.span);
            self.emit(Op::Subscript { dst: s, src, len });
            acc = Some(match acc {
                None => s,
                Some(prev) => {
                    // prev * len + s, computed into `prev` (the element's offset stays small).
                    let n = self.layout.constant(f64::from(len));
                    self.emit(Op::Mul {
                        dst: prev,
                        a: prev,
                        b: n,
                    });
                    self.emit(Op::Add {
                        dst: prev,
                        a: prev,
                        b: s,
                    });
                    self.temp_top = mark;
                    prev
                }
            });
        }
        acc.unwrap_or_else(|| self.layout.constant(0.0))
    }

    /// For an array whose subscripts start above 0 (`OPTION BASE 1`): check the subscript in
    /// `src` against its bounds, before the instructions that take it from 0.
    fn check_subscript(&mut self, el: &Element, sub: &Expr, src: Reg, bound: u32) {
        let known = match sub.kind {
            ExprKind::Const(v) => {
                (f64::from(el.lower)..=f64::from(bound)).contains(&v.round_ties_even())
            }
            _ => false,
        };
        if el.lower > 0 && !known {
            self.emit_ext(ExtOp::CheckSubscript {
                src,
                low: el.lower,
                high: bound,
            });
        }
    }

    /// Store `src` into an array element whose offset is in `off`.
    fn store_element(&mut self, el: &Element, off: Reg, src: Reg) {
        if el.text {
            self.emit_ext(ExtOp::StoreTextAt {
                base: el.base.slot,
                off,
                src,
                len: element_count(el),
            });
            return;
        }
        let decimals = store_kind(el);
        self.emit(Op::StoreAt {
            base: el.base.slot,
            off,
            src,
            decimals,
            len: element_count(el),
        });
    }

    /// Store `src` into a place (a variable or an element).
    fn store_place(&mut self, place: &Place, src: Reg) {
        match place {
            Place::Var(r) if place_is_text(place) => {
                self.emit_ext(ExtOp::StoreText { dst: r.slot, src });
            }
            Place::Var(r) => self.store(r, src),
            Place::Element(el) => self.set_element(el, src),
        }
    }

    /// Store `src` into an element: a constant subscript names the element's own slot, one
    /// subscript is one instruction.
    fn set_element(&mut self, el: &Element, src: Reg) {
        if !el.text {
            if let Some(slot) = constant_element(el) {
                let mut r = el.base.clone();
                r.slot = slot;
                self.store(&r, src);
                return;
            }
            if el.subs.len() == 1 {
                let idx = self.expr(&el.subs[0]);
                self.check_subscript(
                    el,
                    &el.subs[0],
                    idx,
                    el.bounds.first().copied().unwrap_or_default(),
                );
                let decimals = store_kind(el);
                self.emit(Op::StoreIdx {
                    base: el.base.slot,
                    idx,
                    src,
                    len: element_count(el),
                    decimals,
                });
                return;
            }
        }
        let off = self.offset(el);
        self.store_element(el, off, src);
    }

    /// `SWAP a, b`: the subscripts are evaluated once, the first value kept aside (a string in
    /// a cell of its own, since the variable's cell is about to change).
    fn swap(&mut self, a: &Place, b: &Place) {
        let text = place_is_text(a);
        let (sa, oa) = self.locate(a);
        let (sb, ob) = self.locate(b);
        let va = self.read_located(sa, oa);
        let kept = if text {
            let cell = self.layout.cell();
            let dst = self.temp(self.span);
            self.emit_ext(ExtOp::CopyText { dst, cell, src: va });
            dst
        } else {
            va
        };
        let vb = self.read_located(sb, ob);
        let (oa, ob) = (oa.map(|o| o.0), ob.map(|o| o.0));
        self.store_located(a, sa, oa, vb);
        self.store_located(b, sb, ob, kept);
    }

    /// `MID$(v$, start[, n]) = y$`: the place's subscripts evaluated once, its string read,
    /// changed by the string function, and stored back.
    fn mid_set(&mut self, place: &Place, start: &Expr, count: Option<&Expr>, value: &Expr) {
        let (slot, off) = self.locate(place);
        // The function's arguments: v$, start, y$[, n].
        let mut args = [0; 4];
        // A variable is read where it is; an element's value is fetched first.
        args[0] = match off {
            None => slot,
            Some(_) => self.read_located(slot, off),
        };
        let operands = [start, value].into_iter().chain(count);
        for (r, e) in args[1..].iter_mut().zip(operands) {
            *r = self.expr(e);
        }
        let dst = self.temp(self.span);
        let cell = self.layout.cell();
        let argc = 3 + u8::from(count.is_some());
        // Counted as its arguments' copies, the element's read being an instruction of its own.
        let copies = argc - u8::from(off.is_some());
        self.emit_ext_counting(
            ExtOp::Text {
                func: crate::check::text::TextFunc::MidSet,
                dst,
                cell,
                args,
                argc,
                texts: 0b101,
            },
            copies,
        );
        self.store_located(place, slot, off.map(|o| o.0), dst);
    }

    /// Where a place is: its slot, and for an element the register of its offset (kept aside,
    /// so that it survives what is evaluated after it) and the array's length.
    fn locate(&mut self, p: &Place) -> (Reg, Option<(Reg, u32)>) {
        match p {
            Place::Var(r) => (r.slot, None),
            Place::Element(el) => {
                let off = self.offset(el);
                let keep = self.temp(self.span);
                self.emit(Op::Move {
                    dst: keep,
                    src: off,
                });
                (el.base.slot, Some((keep, element_count(el))))
            }
        }
    }

    /// The value of a place found by [`Compiler::locate`].
    fn read_located(&mut self, slot: Reg, off: Option<(Reg, u32)>) -> Reg {
        let dst = self.temp(self.span);
        self.read_into(slot, off, dst);
        dst
    }

    /// [`Compiler::read_located`] into `dst`.
    fn read_into(&mut self, slot: Reg, off: Option<(Reg, u32)>, dst: Reg) {
        match off {
            None => self.emit(Op::Move { dst, src: slot }),
            Some((off, len)) => self.emit(Op::LoadAt {
                dst,
                base: slot,
                off,
                len,
            }),
        };
    }

    /// Store `src` into `place`, found at `slot` (+ `v[off]` for an element).
    fn store_located(&mut self, place: &Place, slot: Reg, off: Option<Reg>, src: Reg) {
        match (place, off) {
            (Place::Element(el), Some(off)) => self.store_element(el, off, src),
            _ if place_is_text(place) => {
                self.emit_ext(ExtOp::StoreText { dst: slot, src });
            }
            (Place::Var(r), _) => self.store(r, src),
            (Place::Element(_), None) => {}
        }
    }

    /// Run an action.
    fn act(&mut self, r: &Resolved, start: StartRef, profile: u8) {
        self.emit(Op::Act {
            hook: r.hook,
            slot: r.slot,
            instance: r.instance,
            start,
            profile,
        });
    }

    /// A motion statement: the operands go to consecutive registers (absent ones are 0), and
    /// an `AFTER` input's slot number after them.
    fn motion(
        &mut self,
        cmd: MotionCmd,
        axis: &Expr,
        operands: &[Option<Expr>],
        after: Option<u32>,
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
        if let (Some(slot), Some(&dst)) = (after, regs.last()) {
            let src = self.layout.constant(f64::from(slot));
            self.emit(Op::Move { dst, src });
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
            _ if e.ty == Ty::Axis => self.expr(e),
            _ => {
                if let ExprKind::Const(n) = e.kind {
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

    /// Drop the range check of `src` this statement just emitted, when the store after it
    /// checks a range as narrow.
    fn drop_check_of(&mut self, src: Reg) {
        if let Some(&(Op::CheckLong { r } | Op::CheckInt { r })) = self.ops.last() {
            if r == src && self.ops.len() > self.stmt_start {
                self.ops.pop();
                self.lines.pop();
                self.spans.pop();
            }
        }
    }

    /// Store `src` into `r` as its type says.
    fn store(&mut self, r: &Resolved, src: Reg) {
        // A MotionBASIC INTEGER: 16 bits; the store checks the range, so a check of the value
        // just computed is not needed.
        if r.kind == Kind::BasicVar && is_int16_name(&r.name) {
            self.drop_check_of(src);
            self.emit(Op::StoreInt { dst: r.slot, src });
            return;
        }
        // A MotionBASIC long integer.
        if r.kind == Kind::BasicVar && r.ty == ValueType::Fixed(0) {
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
                    Some(&Op::IMod { dst, a, b }) if dst == src => Some((BinaryOp::BasicMod, a, b)),
                    Some(&Op::IDiv { dst, a, b }) if dst == src => Some((BinaryOp::IntDiv, a, b)),
                    Some(&Op::BitAnd { dst, a, b }) if dst == src => Some((BinaryOp::BitAnd, a, b)),
                    Some(&Op::BitOr { dst, a, b }) if dst == src => Some((BinaryOp::BitOr, a, b)),
                    Some(&Op::BitXor { dst, a, b }) if dst == src => Some((BinaryOp::BitXor, a, b)),
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
            ExprKind::Bool { value, .. } => {
                if *value == when {
                    vec![self.emit(Op::Jump { target: 0 })]
                } else {
                    Vec::new()
                }
            }
            ExprKind::Paren(inner) => self.jumps(inner, when),
            ExprKind::Not(inner) | ExprKind::BitNot(inner) if inner.truth => {
                self.jumps(inner, !when)
            }
            ExprKind::Binary { op, a, b, .. } if is_and_or(*op) && a.truth && fault_free(b) => {
                // AND jumps on OFF as soon as one side is OFF; OR jumps on ON as soon as one is ON.
                let short = matches!(op, TypedOp::Or | TypedOp::BitOr) == when;
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
            ExprKind::Binary {
                op: TypedOp::Cmp(cmp),
                a,
                b,
                ..
            } if a.ty != Ty::Str => {
                let mark = self.temp_top;
                let ra = self.expr(a);
                let rb = self.expr(b);
                self.temp_top = mark;
                let op = compare_jump(*cmp, ra, rb, when);
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

    /// The cell of the string `e` was just built into, in register `r`, when `e` is a string
    /// function or a join: nothing but the instruction consuming `r` reads that cell before
    /// the same instruction builds it again.
    fn built_cell(&self, e: &Expr, r: Reg) -> Option<u32> {
        let built = match &e.kind {
            ExprKind::Text(..) => true,
            ExprKind::Binary { op, .. } => !matches!(op, TypedOp::Cmp(_)),
            _ => false,
        };
        if !built || e.ty != Ty::Str {
            return None;
        }
        let Some(Op::Ext { at, .. }) = self.ops.last() else {
            return None;
        };
        match self.ext.get(*at as usize) {
            Some(ExtOp::Text { dst, cell, .. } | ExtOp::Concat { dst, cell, .. })
                if *dst == r && *cell != 0 =>
            {
                Some(*cell)
            }
            _ => None,
        }
    }

    /// The values of `args` in consecutive temporaries (a call's arguments), and a fresh
    /// temporary for the result, which may reuse the first argument's.
    fn consecutive(&mut self, args: &[Expr], span: Span) -> (Vec<Reg>, Reg) {
        let mark = self.temp_top;
        let regs: Vec<Reg> = args.iter().map(|_| self.temp(span)).collect();
        let top = self.temp_top;
        for (a, &dst) in args.iter().zip(&regs) {
            let src = self.expr(a);
            self.temp_top = top;
            self.emit(Op::Move { dst, src });
        }
        self.temp_top = mark;
        let dst = self.temp(span);
        (regs, dst)
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
            ExprKind::Const(v) => self.layout.constant(*v),
            ExprKind::Bool { number, .. } => self.layout.constant(*number),
            ExprKind::Read { target, negate } => {
                if *negate {
                    // MotionBASIC's true is -1.
                    let dst = self.temp(e.span);
                    self.emit(Op::Neg {
                        dst,
                        a: target.slot,
                    });
                    return dst;
                }
                target.slot
            }
            ExprKind::Paren(inner) => self.expr(inner),
            ExprKind::Str(text) => {
                let id = self.layout.string(text);
                self.layout.constant(id)
            }
            ExprKind::AxisSet(_) => self.axis_set(e),
            ExprKind::Neg(inner) | ExprKind::Not(inner) | ExprKind::BitNot(inner) => {
                let mark = self.temp_top;
                let a = self.expr(inner);
                self.temp_top = mark;
                let dst = self.temp(e.span);
                let negative = matches!(e.kind, ExprKind::Neg(_));
                self.emit(match e.kind {
                    ExprKind::Neg(_) => Op::Neg { dst, a },
                    ExprKind::Not(_) => Op::Not { dst, a },
                    _ => Op::BitNot { dst, a },
                });
                if negative && e.int16 {
                    self.emit(Op::CheckInt { r: dst });
                } else if negative && e.long {
                    self.emit(Op::CheckLong { r: dst });
                }
                dst
            }
            ExprKind::Binary { op, a, b, negate } if a.ty == Ty::Str => {
                let mark = self.temp_top;
                let ra = self.expr(a);
                let fresh_cell = self.built_cell(a, ra);
                let rb = self.expr(b);
                self.temp_top = mark;
                let dst = self.temp(e.span);
                match op {
                    TypedOp::Cmp(cmp) => {
                        self.emit_ext(ExtOp::CompareText {
                            cmp: *cmp,
                            dst,
                            a: ra,
                            b: rb,
                        });
                        if *negate {
                            self.emit(Op::Neg { dst, a: dst });
                        }
                    }
                    _ => {
                        // A string this expression just built (a function's or a join's) is
                        // consumed here: its cell takes `b` in place of a copy.
                        let cell = match fresh_cell {
                            Some(cell) => cell,
                            None => self.layout.cell(),
                        };
                        self.emit_ext(ExtOp::Concat {
                            dst,
                            cell,
                            a: ra,
                            b: rb,
                        });
                    }
                }
                dst
            }
            ExprKind::Element(el) if el.subs.len() == 1 => {
                if let Some(slot) = constant_element(el) {
                    return slot;
                }
                let mark = self.temp_top;
                let idx = self.expr(&el.subs[0]);
                self.check_subscript(
                    el,
                    &el.subs[0],
                    idx,
                    el.bounds.first().copied().unwrap_or_default(),
                );
                self.temp_top = mark;
                let dst = self.temp(e.span);
                self.emit(Op::LoadIdx {
                    dst,
                    base: el.base.slot,
                    idx,
                    len: element_count(el),
                });
                dst
            }
            ExprKind::Element(el) => {
                let mark = self.temp_top;
                let off = self.offset(el);
                self.temp_top = mark;
                let dst = self.temp(e.span);
                self.emit(Op::LoadAt {
                    dst,
                    base: el.base.slot,
                    off,
                    len: element_count(el),
                });
                dst
            }
            ExprKind::Text(func, args) => {
                // Each argument is read where it is: a variable in its own slot, no copy.
                let mark = self.temp_top;
                let mut regs = [0; 4];
                for (r, a) in regs.iter_mut().zip(args) {
                    *r = self.expr(a);
                }
                self.temp_top = mark;
                let dst = self.temp(e.span);
                let cell = if e.ty == Ty::Str {
                    self.layout.cell()
                } else {
                    0
                };
                let texts = args
                    .iter()
                    .enumerate()
                    .filter(|(_, a)| a.ty == Ty::Str)
                    .fold(0u8, |m, (i, _)| m | (1 << i));
                let argc = args.len() as u8;
                self.emit_ext_counting(
                    ExtOp::Text {
                        func: *func,
                        dst,
                        cell,
                        args: regs,
                        argc,
                        texts,
                    },
                    argc,
                );
                dst
            }
            ExprKind::Rnd(arg) => {
                let mark = self.temp_top;
                let arg = arg.as_ref().map(|a| self.expr(a));
                self.temp_top = mark;
                let dst = self.temp(e.span);
                self.emit_ext(ExtOp::Rnd { dst, arg });
                dst
            }
            ExprKind::Timer => {
                let dst = self.temp(e.span);
                self.emit_ext(ExtOp::Timer { dst });
                dst
            }
            ExprKind::Binary { op, a, b, negate } => {
                let mark = self.temp_top;
                let ra = self.expr(a);
                let rb = self.expr(b);
                self.temp_top = mark;
                let dst = self.temp(e.span);
                let (a, b) = (ra, rb);
                let binary = |op| Op::Binary { op, dst, a, b };
                let instruction = match op {
                    TypedOp::Add => Op::Add { dst, a, b },
                    TypedOp::Sub => Op::Sub { dst, a, b },
                    TypedOp::Mul => Op::Mul { dst, a, b },
                    TypedOp::Div => Op::Div { dst, a, b },
                    TypedOp::Mod => Op::Mod { dst, a, b },
                    TypedOp::BasicMod => Op::IMod { dst, a, b },
                    TypedOp::IntDiv => Op::IDiv { dst, a, b },
                    TypedOp::Pow => binary(BinaryOp::Pow),
                    TypedOp::And => binary(BinaryOp::And),
                    TypedOp::Or => binary(BinaryOp::Or),
                    TypedOp::Xor => binary(BinaryOp::Xor),
                    TypedOp::BitAnd => Op::BitAnd { dst, a, b },
                    TypedOp::BitOr => Op::BitOr { dst, a, b },
                    TypedOp::BitXor => Op::BitXor { dst, a, b },
                    TypedOp::Cmp(cmp) => Op::Compare {
                        cmp: *cmp,
                        dst,
                        a,
                        b,
                    },
                };
                self.emit(instruction);
                if *negate {
                    // MotionBASIC's comparisons give -1 or 0.
                    self.emit(Op::Neg { dst, a: dst });
                } else if e.int16 {
                    // 16-bit INTEGER arithmetic (`\` too: -32768 \ -1).
                    self.emit(Op::CheckInt { r: dst });
                } else if e.long && matches!(op, TypedOp::Add | TypedOp::Sub | TypedOp::Mul) {
                    self.emit(Op::CheckLong { r: dst });
                }
                dst
            }
            ExprKind::AxisRead {
                member,
                truth,
                axes,
            } => {
                let mark = self.temp_top;
                let axes = self.axis_set(axes);
                self.temp_top = mark;
                let dst = self.temp(e.span);
                self.emit(Op::AxisRead {
                    dst,
                    axes,
                    member: *member,
                    truth: *truth,
                });
                dst
            }
            ExprKind::Kernel { func, args, negate } => {
                let (regs, dst) = self.consecutive(args, e.span);
                let args = regs.first().copied().unwrap_or(dst);
                self.emit(Op::KernelCall {
                    func: *func,
                    dst,
                    args,
                });
                if *negate {
                    // REGIST's and WRITE_SV's OK is a truth value: -1 in MotionBASIC.
                    self.emit(Op::Neg { dst, a: dst });
                }
                dst
            }
            ExprKind::Call(func, args) => {
                let mark = self.temp_top;
                let a = args.first().map_or(0, |x| self.expr(x));
                let b = args.get(1).map_or(a, |x| self.expr(x));
                self.temp_top = mark;
                let dst = self.temp(e.span);
                self.emit(Op::Call {
                    func: *func,
                    dst,
                    a,
                    b,
                });
                dst
            }
        }
    }
}

/// `AND`/`OR` of either kind (ON/OFF, or MotionBASIC's bitwise on truth values).
fn is_and_or(op: TypedOp) -> bool {
    matches!(
        op,
        TypedOp::And | TypedOp::Or | TypedOp::BitAnd | TypedOp::BitOr
    )
}

/// The selector and the cases of the `IF`s an `ON n GOTO`/`ON n GOSUB` stands for
/// (`syntax::lines::on_jump`): each compares `CINT(n)` with its number, 1 first, and holds one
/// `GOTO` or `GOSUB`, the next in its `ELSE`. Every `CINT(n)` is the same copy of `n`, at the
/// same place in the source (which two calls written apart never are). `None` for any other
/// `IF`, or an `ON` of one case (its `IF` is all there is).
fn on_cases(kind: &StmtKind) -> Option<(&Expr, Vec<&[Stmt]>)> {
    let mut cases: Vec<&[Stmt]> = Vec::new();
    let mut selector: Option<&Expr> = None;
    let mut at = kind;
    loop {
        let StmtKind::If {
            cond,
            then_body,
            else_body,
        } = at
        else {
            return None;
        };
        let ExprKind::Binary {
            op: TypedOp::Cmp(Cmp::Eq),
            a,
            b,
            ..
        } = &cond.kind
        else {
            return None;
        };
        let number = (cases.len() + 1) as f64;
        if !matches!(a.kind, ExprKind::Call(Func::Cint, _)) || b.kind != ExprKind::Const(number) {
            return None;
        }
        match selector {
            None => selector = Some(&**a),
            Some(first) if first.span == a.span && *first == **a => {}
            Some(_) => return None,
        }
        if !matches!(
            then_body.as_slice(),
            [Stmt {
                kind: StmtKind::Goto(_) | StmtKind::Gosub(_),
                ..
            }]
        ) {
            return None;
        }
        cases.push(then_body);
        match else_body.as_deref() {
            None => break,
            Some([next]) => at = &next.kind,
            Some(_) => return None,
        }
    }
    Some((selector?, cases)).filter(|(_, c)| c.len() > 1)
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
        ExprKind::Const(_) | ExprKind::Bool { .. } | ExprKind::Read { .. } | ExprKind::Str(_) => {
            true
        }
        ExprKind::Paren(x) | ExprKind::Neg(x) | ExprKind::Not(x) | ExprKind::BitNot(x) => {
            fault_free(x)
        }
        ExprKind::Binary {
            op: TypedOp::Div | TypedOp::Mod | TypedOp::BasicMod,
            a,
            b,
            ..
        } => fault_free(a) && matches!(b.kind, ExprKind::Const(v) if v != 0.0),
        ExprKind::Binary { a, b, .. } => fault_free(a) && fault_free(b),
        // Math functions cannot fail; kernel functions and controller variables can (a wrong
        // axis) or act.
        ExprKind::Call(_, args) => args.iter().all(fault_free),
        ExprKind::AxisSet(args) => args.iter().all(fault_free),
        ExprKind::Kernel { .. } | ExprKind::AxisRead { .. } => false,
        // A subscript can be out of range; a string function can be an illegal call; RND
        // changes the generator.
        ExprKind::Element(_) | ExprKind::Text(..) | ExprKind::Rnd(_) => false,
        ExprKind::Timer => true,
    }
}

/// How an element of this array is stored (`StoreAt`/`StoreIdx`'s `decimals`).
fn store_kind(el: &Element) -> u8 {
    match el.base.ty {
        _ if is_int16_name(&el.base.name) => INT_STORE,
        ValueType::Fixed(d) => d,
        ValueType::Integer => 0,
        _ => REAL_STORE,
    }
}

/// The slot of an element whose subscripts are all constants within its bounds (the checker
/// refused others it could see).
fn constant_element(el: &Element) -> Option<Reg> {
    let mut off: u32 = 0;
    for (sub, &bound) in el.subs.iter().zip(&el.bounds) {
        let ExprKind::Const(v) = sub.kind else {
            return None;
        };
        let i = v.round_ties_even();
        if !(f64::from(el.lower)..=f64::from(bound)).contains(&i) {
            return None;
        }
        off = off * (bound + 1) + i as u32;
    }
    Some(el.base.slot + off)
}

/// The number of elements of an element's array.
fn element_count(el: &Element) -> u32 {
    el.bounds.iter().map(|&b| b + 1).product()
}

/// Whether a place holds a string.
fn place_is_text(place: &Place) -> bool {
    match place {
        Place::Var(r) => r.kind == Kind::BasicVar && is_text_name(&r.name),
        Place::Element(el) => el.text,
    }
}
