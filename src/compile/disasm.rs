//! A readable listing of compiled bytecode (`pacer disasm`).

use super::bytecode::{BinaryOp, ExtOp, Op, StartRef};
use super::{Chunk, Layout};
use crate::registry::Registry;
use std::fmt::Write;

/// Render a chunk: one instruction a line, with its source line, its operands' names and,
/// after `;`, the line and column of the expression or statement it evaluates.
pub fn disassemble(chunk: &Chunk, layout: &Layout, registry: &Registry) -> String {
    let r = |x: u32| layout.describe(x, registry);
    // A string operand: a constant is shown as the string, not as its index.
    let text = |x: u32| {
        let shown = r(x);
        match shown
            .parse::<usize>()
            .ok()
            .and_then(|i| layout.strings.get(i))
        {
            Some(literal) => format!("{literal:?}"),
            None => shown,
        }
    };
    let mut out = String::new();
    let _ = writeln!(
        out,
        "; Program.{} ({}) — {} instructions",
        chunk.program,
        chunk.file,
        chunk.ops.len()
    );
    let mut last_line = 0;
    for (pc, op) in chunk.ops.iter().enumerate() {
        let line = chunk.lines.get(pc).copied().unwrap_or(0);
        let line_col = if line != last_line {
            format!("{line:>4}")
        } else {
            "    ".to_string()
        };
        last_line = line;
        let text = match *op {
            Op::Move { dst, src } => format!("move      {} <- {}", r(dst), r(src)),
            Op::Add { dst, a, b } => format!("add       {} <- {} + {}", r(dst), r(a), r(b)),
            Op::Sub { dst, a, b } => format!("sub       {} <- {} - {}", r(dst), r(a), r(b)),
            Op::Mul { dst, a, b } => format!("mul       {} <- {} * {}", r(dst), r(a), r(b)),
            Op::Div { dst, a, b } | Op::DivReal { t: dst, a, b, .. } => {
                format!("div       {} <- {} / {}", r(dst), r(a), r(b))
            }
            Op::Mod { dst, a, b } => format!("mod       {} <- {} MOD {}", r(dst), r(a), r(b)),
            Op::AddFixed {
                dst,
                a,
                b,
                decimals,
            } => fused("add", decimals, r(dst), r(a), "+", r(b)),
            Op::SubFixed {
                dst,
                a,
                b,
                decimals,
            } => fused("sub", decimals, r(dst), r(a), "-", r(b)),
            Op::MulFixed {
                dst,
                a,
                b,
                decimals,
            } => fused("mul", decimals, r(dst), r(a), "*", r(b)),
            Op::ArithFixed {
                op,
                dst,
                a,
                b,
                decimals,
            } => {
                let (name, sym) = op_names(op);
                fused(name, decimals, r(dst), r(a), sym, r(b))
            }
            Op::Binary { op, dst, a, b } => {
                let (name, sym) = op_names(op);
                format!("{name:<9} {} <- {} {sym} {}", r(dst), r(a), r(b))
            }
            Op::IMod { dst, a, b } => format!("imod      {} <- {} MOD {}", r(dst), r(a), r(b)),
            Op::IDiv { dst, a, b } => format!("idiv      {} <- {} \\ {}", r(dst), r(a), r(b)),
            Op::BitAnd { dst, a, b } => format!("band      {} <- {} AND {}", r(dst), r(a), r(b)),
            Op::BitOr { dst, a, b } => format!("bor       {} <- {} OR {}", r(dst), r(a), r(b)),
            Op::BitXor { dst, a, b } => format!("bxor      {} <- {} XOR {}", r(dst), r(a), r(b)),
            // A superinstruction is listed as the first of the two instructions it runs; the
            // second follows it.
            Op::AddLong { t, a, b, .. }
            | Op::AddInt { t, a, b, .. }
            | Op::AddReal { t, a, b, .. }
            | Op::AddAdd { t, a, b, .. }
            | Op::AddSub { t, a, b, .. }
            | Op::AddMul { t, a, b, .. } => {
                format!("add       {} <- {} + {}", r(t), r(a), r(b))
            }
            Op::SubLong { t, a, b, .. }
            | Op::SubInt { t, a, b, .. }
            | Op::SubReal { t, a, b, .. }
            | Op::SubAdd { t, a, b, .. }
            | Op::SubSub { t, a, b, .. }
            | Op::SubMul { t, a, b, .. } => {
                format!("sub       {} <- {} - {}", r(t), r(a), r(b))
            }
            Op::MulLong { t, a, b, .. }
            | Op::MulInt { t, a, b, .. }
            | Op::MulReal { t, a, b, .. } => {
                format!("mul       {} <- {} * {}", r(t), r(a), r(b))
            }
            Op::IntLong { op, t, a, b, .. } | Op::IntInt { op, t, a, b, .. } => {
                let (name, sym) = op_names(op);
                format!("{name:<9} {} <- {} {sym} {}", r(t), r(a), r(b))
            }
            Op::ModLong { t, a, b, .. } => {
                format!("imod      {} <- {} MOD {}", r(t), r(a), r(b))
            }
            Op::AndLong { t, a, b, .. } => {
                format!("band      {} <- {} AND {}", r(t), r(a), r(b))
            }
            Op::OrLong { t, a, b, .. } => format!("bor       {} <- {} OR {}", r(t), r(a), r(b)),
            Op::XorLong { t, a, b, .. } => {
                format!("bxor      {} <- {} XOR {}", r(t), r(a), r(b))
            }
            Op::MulAdd { t, a, b, .. }
            | Op::MulAcc { p: t, a, b, .. }
            | Op::MulDec { p: t, a, b, .. } => format!("mul       {} <- {} * {}", r(t), r(a), r(b)),
            Op::MulSumReal { acc, a, b, .. } => {
                format!("mul       {} <- {} * {}", r(acc + 1), r(a), r(b))
            }
            Op::MulAddCheck { t, a, b, .. }
            | Op::MulAddCheckModLong { t, a, b, .. }
            | Op::MulAddModWhole { t, a, b } => {
                format!("mul       {} <- {} * {}", r(t), r(a), r(b))
            }
            Op::AddModLong { t, x, t_first, .. } | Op::AddModWhole { t, x, t_first, .. } => {
                let (p, q) = if t_first { (t, x) } else { (x, t) };
                format!("add       {} <- {} + {}", r(t), r(p), r(q))
            }
            Op::AndOr { t, a, b, .. }
            | Op::AndJump { t, a, b, .. }
            | Op::AndXorLong { t, a, b, .. }
            | Op::AndXorWhole { t, a, b, .. } => {
                format!("band      {} <- {} AND {}", r(t), r(a), r(b))
            }
            Op::SubMod { t, a, b, .. } | Op::QuotAddFixed { t, a, b } => {
                format!("mod       {} <- {} MOD {}", r(t), r(a), r(b))
            }
            Op::DivAddFixed { t, a, b, .. } => {
                format!("div       {} <- {} / {}", r(t), r(a), r(b))
            }
            Op::DivAddLong { t, a, b, .. } => {
                format!("idiv      {} <- {} \\ {}", r(t), r(a), r(b))
            }
            Op::NotAndLong { t, a, .. } | Op::NotAndWhole { t, a, .. } => {
                format!("bnot      {} <- NOT {}", r(t), r(a))
            }
            Op::JumpNext { at, .. } => format!("jump      @{at}"),
            // Specialisations of `ArithFixed` (one instruction each), listed as it is.
            Op::ModWhole { dst, a, b } => fused("mod", 0, r(dst), r(a), "MOD", r(b)),
            Op::AndWhole { dst, a, b } => fused("band", 0, r(dst), r(a), "AND", r(b)),
            Op::OrWhole { dst, a, b } => fused("bor", 0, r(dst), r(a), "OR", r(b)),
            Op::XorWhole { dst, a, b } => fused("bxor", 0, r(dst), r(a), "XOR", r(b)),
            Op::AddCheck { dst, a, b } | Op::AddCheckInt { dst, a, b } => {
                format!("add       {} <- {} + {}", r(dst), r(a), r(b))
            }
            Op::SubCheck { dst, a, b } | Op::SubCheckInt { dst, a, b } => {
                format!("sub       {} <- {} - {}", r(dst), r(a), r(b))
            }
            Op::MulCheck { dst, a, b } | Op::MulCheckInt { dst, a, b } => {
                format!("mul       {} <- {} * {}", r(dst), r(a), r(b))
            }
            Op::Compare { cmp, dst, a, b } => {
                format!("cmp       {} <- {} {} {}", r(dst), r(a), cmp.symbol(), r(b))
            }
            Op::Neg { dst, a } => format!("neg       {} <- -{}", r(dst), r(a)),
            // A sum is listed as its first product, the rest of its instructions following.
            Op::SumReal { acc, at, .. } => match chunk.terms.get(at as usize + 1) {
                Some(first) => format!("mul       {} <- {} * {}", r(acc), r(first.a), r(first.b)),
                None => format!("mul       {} <- ?", r(acc)),
            },
            Op::Not { dst, a } => format!("not       {} <- NOT {}", r(dst), r(a)),
            Op::BitNot { dst, a } => format!("bnot      {} <- NOT {}", r(dst), r(a)),
            Op::Call { func, dst, a, b } => {
                if a == b {
                    format!("call      {} <- {}({})", r(dst), func.name(), r(a))
                } else {
                    format!(
                        "call      {} <- {}({}, {})",
                        r(dst),
                        func.name(),
                        r(a),
                        r(b)
                    )
                }
            }
            Op::StoreFixed { dst, src, decimals } => {
                format!(
                    "{:<9} {} <- {}",
                    format!("store.f{decimals}"),
                    r(dst),
                    r(src)
                )
            }
            Op::StoreReal { dst, src } => format!("store.r   {} <- {}", r(dst), r(src)),
            Op::StoreBit { dst, src } => format!("store.b   {} <- {}", r(dst), r(src)),
            Op::Write {
                hook, slot, src, ..
            } => format!("write     {} <- {}   ; {hook:?}", r(slot), r(src)),
            Op::Act {
                hook,
                slot,
                start,
                profile,
                ..
            } => {
                let mut s = format!("act       {}", r(slot));
                match start {
                    StartRef::Now => {}
                    StartRef::Last => s.push_str(" using last"),
                    StartRef::Capture(c) => {
                        let _ = write!(s, " using Capture.{c}");
                    }
                }
                if profile != 0 {
                    let _ = write!(s, " on Profile.{profile}");
                }
                let _ = write!(s, "   ; {hook:?}");
                s
            }
            Op::Jump { target } => format!("jump      @{target}"),
            Op::Loop { target } | Op::LoopTight { target } => format!("loop      @{target}"),
            Op::JumpIfFalse { cond, target } => format!("jump.f    {} @{target}", r(cond)),
            Op::JumpUnlessLt { a, b, target } => format!("jump.not  {} < {} @{target}", r(a), r(b)),
            Op::JumpUnlessLe { a, b, target } => {
                format!("jump.not  {} <= {} @{target}", r(a), r(b))
            }
            Op::JumpUnlessEq { a, b, target } => format!("jump.not  {} = {} @{target}", r(a), r(b)),
            Op::JumpUnlessNe { a, b, target } => {
                format!("jump.not  {} <> {} @{target}", r(a), r(b))
            }
            Op::JumpWhenLt { a, b, target } => format!("jump.if   {} < {} @{target}", r(a), r(b)),
            Op::JumpWhenLe { a, b, target } => format!("jump.if   {} <= {} @{target}", r(a), r(b)),
            Op::JumpWhenEq { a, b, target } => format!("jump.if   {} = {} @{target}", r(a), r(b)),
            Op::JumpWhenNe { a, b, target } => format!("jump.if   {} <> {} @{target}", r(a), r(b)),
            Op::JumpIfTrue { cond, target } => format!("jump.t    {} @{target}", r(cond)),
            Op::ForNext {
                var, limit, body, ..
            } => {
                format!(
                    "for.next  {} += {} to {} body @{body}",
                    r(var),
                    r(limit + 1),
                    r(limit)
                )
            }
            Op::WaitUntil { cond, retry } => format!("wait      {} (retry @{retry})", r(cond)),
            Op::WaitTime { src } => format!("wait.time {} s", r(src)),
            Op::Dwell { src, master, last } => format!(
                "dwell     {} {}{}",
                r(src),
                if master { "master units" } else { "s" },
                if last { " using last" } else { "" }
            ),
            Op::ForCheck { var, limit, exit }
            | Op::ForTight {
                var, limit, exit, ..
            } => {
                format!(
                    "for.check {} to {} step {} exit @{exit}",
                    r(var),
                    r(limit),
                    r(limit + 1)
                )
            }
            Op::CallProgram { program } => format!("call      Program.{program}"),
            Op::CheckLong { r: x } => format!("chk.long  {}", r(x)),
            Op::CheckInt { r: x } => format!("chk.int   {}", r(x)),
            Op::StoreLong { dst, src } => format!("store.l   {} <- {}", r(dst), r(src)),
            Op::StoreInt { dst, src } => format!("store.i   {} <- {}", r(dst), r(src)),
            Op::AxisBit { dst, a } => format!("axis      {} <- {{{}}}", r(dst), r(a)),
            Op::AxisRead {
                dst,
                axes,
                member,
                truth,
            } => format!(
                "axis.rd   {} <- Axis[{}].{}{}",
                r(dst),
                r(axes),
                axis_member_name(member),
                if truth { " (truth)" } else { "" }
            ),
            Op::AxisWrite {
                axes, src, member, ..
            } => format!(
                "axis.wr   Axis[{}].{} <- {}",
                r(axes),
                axis_member_name(member),
                r(src)
            ),
            Op::Motion { cmd, axes, args } => {
                format!("motion    {cmd:?} Axis[{}] args from {}", r(axes), r(args))
            }
            Op::KernelCall { func, dst, args } => {
                format!(
                    "kcall     {} <- {}(args from {})",
                    r(dst),
                    func.name(),
                    r(args)
                )
            }
            Op::Print { src, how } => {
                let shown = if how == crate::compile::bytecode::PrintHow::Text {
                    text(src)
                } else {
                    r(src)
                };
                format!("print     {shown} as {how:?}")
            }
            Op::PrintZone => "print.zone".to_string(),
            Op::PrintLine => "print.line".to_string(),
            Op::Gosub { target } => format!("gosub     @{target}"),
            Op::Subscript { dst, src, len } => {
                format!("subscr    {} <- {} in 0..{}", r(dst), r(src), len)
            }
            Op::Offset2 { p, i, lens, .. } => {
                format!("subscr    {} <- {} in 0..{}", r(p), r(i), lens >> 16)
            }
            Op::OffsetTail { p, x, len } => {
                format!("subscr    {} <- {} in 0..{}", r(p + 1), r(x), len)
            }
            Op::LoadIdx {
                dst,
                base,
                idx,
                len,
            } => {
                format!(
                    "load.idx  {} <- {}[{} in 0..{len}]",
                    r(dst),
                    r(base),
                    r(idx)
                )
            }
            Op::StoreIdx {
                base,
                idx,
                src,
                len,
                decimals,
            }
            | Op::StoreIdxNext {
                base,
                idx,
                src,
                len,
                decimals,
            } => {
                let kind = store_kind(decimals);
                format!(
                    "store.idx.{kind} {}[{} in 0..{len}] <- {}",
                    r(base),
                    r(idx),
                    r(src)
                )
            }
            Op::LoadAt { dst, base, off, .. } => {
                format!("load.at   {} <- {}[{}]", r(dst), r(base), r(off))
            }
            Op::StoreAt {
                base,
                off,
                src,
                decimals,
                ..
            } => {
                let kind = store_kind(decimals);
                format!("store.at.{kind} {}[{}] <- {}", r(base), r(off), r(src))
            }
            Op::Ext { at, .. } | Op::ExtPair { at, .. } | Op::TextJump { at, .. } => {
                match chunk.ext.get(at as usize) {
                    Some(ext) => ext_text(ext, &r, &text, chunk),
                    None => format!("ext       #{at}?"),
                }
            }
            Op::Return => "return".to_string(),
            Op::End => "end".to_string(),
        };
        // Where in the source the instruction's expression or statement starts.
        let (l, c) = chunk
            .spans
            .get(pc)
            .map_or((0, 0), |s| chunk.source.line_col(*s));
        let _ = writeln!(out, "{line_col} @{pc:<4} {text:<48} ; {l}:{c}");
    }
    out
}

fn op_names(op: BinaryOp) -> (&'static str, &'static str) {
    match op {
        BinaryOp::Add => ("add", "+"),
        BinaryOp::Sub => ("sub", "-"),
        BinaryOp::Mul => ("mul", "*"),
        BinaryOp::Div => ("div", "/"),
        BinaryOp::Mod => ("mod", "MOD"),
        BinaryOp::Pow => ("pow", "^"),
        BinaryOp::And => ("and", "AND"),
        BinaryOp::Or => ("or", "OR"),
        BinaryOp::Xor => ("xor", "XOR"),
        BinaryOp::BitAnd => ("band", "AND"),
        BinaryOp::BitOr => ("bor", "OR"),
        BinaryOp::BitXor => ("bxor", "XOR"),
        BinaryOp::IntDiv => ("idiv", "\\"),
        BinaryOp::BasicMod => ("imod", "MOD"),
    }
}

fn axis_member_name(member: u8) -> &'static str {
    crate::registry::catalog::find_type("Axis")
        .and_then(|d| d.members.get(member as usize))
        .map_or("?", |m| m.name)
}

fn fused(name: &str, decimals: u8, dst: String, a: String, sym: &str, b: String) -> String {
    let mnemonic = format!("{name}.f{decimals}");
    format!("{mnemonic:<9} {dst} <- {a} {sym} {b}")
}

/// An [`Op::Ext`] instruction as the disassembly shows it.
fn ext_text(
    op: &ExtOp,
    r: &dyn Fn(u32) -> String,
    text: &dyn Fn(u32) -> String,
    chunk: &Chunk,
) -> String {
    match op {
        ExtOp::StoreText { dst, src } => format!("store.s   {} <- {}", r(*dst), text(*src)),
        ExtOp::StoreTextAt { base, off, src, .. } => {
            format!("store.at.s {}[{}] <- {}", r(*base), r(*off), text(*src))
        }
        ExtOp::CopyText { dst, cell, src } => {
            format!("copy.s    {} <- {} (cell {cell})", r(*dst), text(*src))
        }
        ExtOp::Concat { dst, cell, a, b } => {
            format!(
                "concat    {} <- {} + {} (cell {cell})",
                r(*dst),
                text(*a),
                text(*b)
            )
        }
        ExtOp::Text {
            func,
            dst,
            cell,
            args,
            argc,
            texts,
        } => {
            let args: Vec<String> = args[..usize::from(*argc)]
                .iter()
                .enumerate()
                .map(|(i, &a)| if texts & (1 << i) != 0 { text(a) } else { r(a) })
                .collect();
            format!(
                "text      {} <- {}{}({}){}",
                r(*dst),
                func.name(),
                // The statement's function, not the one of the same name.
                if *func == crate::check::text::TextFunc::MidSet {
                    "="
                } else {
                    ""
                },
                args.join(", "),
                if *cell == 0 {
                    String::new()
                } else {
                    format!(" (cell {cell})")
                }
            )
        }
        ExtOp::CompareText { cmp, dst, a, b } => format!(
            "cmp.s     {} <- {} {} {}",
            r(*dst),
            text(*a),
            cmp.symbol(),
            text(*b)
        ),
        ExtOp::Rnd { dst, arg } => match arg {
            Some(a) => format!("rnd       {} <- RND({})", r(*dst), r(*a)),
            None => format!("rnd       {} <- RND", r(*dst)),
        },
        ExtOp::Randomize { seed } => match seed {
            Some(s) => format!("randomize {}", r(*s)),
            None => "randomize (the scenario's seed)".to_string(),
        },
        ExtOp::Timer { dst } => format!("timer     {}", r(*dst)),
        ExtOp::CheckSubscript { src, low, high } => {
            format!("check.sub {} in {low}..={high}", r(*src))
        }
        ExtOp::Read { dst, text } => {
            format!(
                "read      {} <- DATA{}",
                r(*dst),
                if *text { " (string)" } else { "" }
            )
        }
        ExtOp::PrintUsing {
            format,
            args,
            count,
            ..
        } => format!("print.using {} ; {count} from {}", r(*format), r(*args)),
        // Listed as the `text` instruction each stands for.
        ExtOp::Len { .. }
        | ExtOp::Asc { .. }
        | ExtOp::Val { .. }
        | ExtOp::Instr { .. }
        | ExtOp::Left { .. }
        | ExtOp::Right { .. }
        | ExtOp::Mid { .. }
        | ExtOp::MidN { .. }
        | ExtOp::Chr { .. }
        | ExtOp::Str { .. } => ext_text(&op.general(), r, text, chunk),
        ExtOp::Restore { item } => {
            let line = chunk.data.get(*item as usize).map(|d| d.line);
            match line {
                Some(l) => format!("restore   DATA #{item} (line {l})"),
                None => format!("restore   DATA #{item}"),
            }
        }
    }
}

/// How a store rounds, as the disassembly's suffix: `r` real, `i` INTEGER, `l` long, `fN` N
/// decimals.
fn store_kind(decimals: u8) -> String {
    match decimals {
        crate::compile::bytecode::REAL_STORE => "r".to_string(),
        crate::compile::bytecode::INT_STORE => "i".to_string(),
        0 => "l".to_string(),
        d => format!("f{d}"),
    }
}
