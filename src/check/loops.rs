//! PowerTools loops that never wait: a `Do While` or a backward `Goto` whose body has no statement
//! that can block (a wait, a dwell, a motion start, a call, a MotionBASIC motion statement) and
//! whose condition nothing in the body changes. Such a loop spins for its task's whole
//! instruction budget every update — on the drive as in pacer — which is seldom what was meant
//! (a poll is a `Wait For`). A warning, not an error: a PLC-style scan loop is legal.

use super::typed::{each_stmt, Expr, ExprKind, Program, Stmt, StmtKind};
use crate::diag::Problem;
use crate::registry::{Hook, Kind, SlotId};

/// What a statement or expression touches: slots, and object instances (an action changes its
/// object's status members).
#[derive(Default)]
struct Touched {
    slots: Vec<SlotId>,
    objects: Vec<(Kind, u32)>,
}

impl Touched {
    fn meets(&self, other: &Touched) -> bool {
        self.slots.iter().any(|s| other.slots.contains(s))
            || self.objects.iter().any(|o| other.objects.contains(o))
    }
}

/// Warn about every loop of `program` that never waits.
pub fn busy_loops(program: &Program, problems: &mut Vec<Problem>) {
    block(&program.body, problems);
}

fn block(stmts: &[Stmt], problems: &mut Vec<Problem>) {
    for (j, s) in stmts.iter().enumerate() {
        match &s.kind {
            StmtKind::While { cond, body } => {
                let mut read = Touched::default();
                expr_reads(cond, &mut read);
                let mut written = Touched::default();
                writes(body, &mut written);
                if !blocks(body) && !read.meets(&written) {
                    problems.push(warning(s));
                }
                block(body, problems);
            }
            StmtKind::For { body, .. } => block(body, problems),
            StmtKind::If {
                then_body,
                else_body,
                ..
            } => {
                block(then_body, problems);
                block(else_body.as_deref().unwrap_or_default(), problems);
            }
            _ => {}
        }
        // A backward jump to a label of this block: the statements from the label to here loop.
        for target in gotos(s) {
            let label = stmts[..=j]
                .iter()
                .position(|l| matches!(&l.kind, StmtKind::Label(name) if *name == target));
            let Some(i) = label else { continue };
            let body = &stmts[i..=j];
            let conditional = !matches!(s.kind, StmtKind::Goto(_));
            let mut read = Touched::default();
            if conditional {
                conditions(s, &mut read);
            }
            let mut written = Touched::default();
            writes(body, &mut written);
            let ends_by_itself = conditional && read.meets(&written);
            if !blocks(body) && !ends_by_itself {
                problems.push(warning(&stmts[i]));
            }
        }
    }
}

fn warning(s: &Stmt) -> Problem {
    Problem::warning(
        "pacer::check::busy_loop",
        s.span,
        "this loop never waits",
        "loops without waiting",
    )
    .with_help(
        "nothing in it can block and nothing in it changes its condition, so each update its \
         task spends its whole instruction budget going round; to poll something, write \
         `Wait For <condition>` (a loop that must scan without waiting may stay as it is)",
    )
}

/// The labels `s` jumps to, outside nested loops (an `If`'s branches included).
fn gotos(s: &Stmt) -> Vec<String> {
    match &s.kind {
        StmtKind::Goto(label) => vec![label.clone()],
        StmtKind::If {
            then_body,
            else_body,
            ..
        } => then_body
            .iter()
            .chain(else_body.iter().flatten())
            .flat_map(gotos)
            .collect(),
        _ => Vec::new(),
    }
}

/// The conditions guarding `s`'s jumps (an `If`'s, nested ones included).
fn conditions(s: &Stmt, out: &mut Touched) {
    if let StmtKind::If {
        cond,
        then_body,
        else_body,
    } = &s.kind
    {
        expr_reads(cond, out);
        for inner in then_body.iter().chain(else_body.iter().flatten()) {
            conditions(inner, out);
        }
    }
}

/// A statement of `stmts` (nested ones included) can block its task.
fn blocks(stmts: &[Stmt]) -> bool {
    let mut found = false;
    each_stmt(stmts, &mut |s| {
        found |= match &s.kind {
            StmtKind::WaitFor(_)
            | StmtKind::WaitTime(_)
            | StmtKind::Dwell { .. }
            | StmtKind::Call(_)
            | StmtKind::Gosub(_)
            | StmtKind::Motion { .. } => true,
            StmtKind::Act { target, .. } => target.hook == Hook::MotionStart,
            _ => false,
        }
    });
    found
}

/// What `stmts` (nested ones included) write or act on.
fn writes(stmts: &[Stmt], out: &mut Touched) {
    each_stmt(stmts, &mut |s| match &s.kind {
        StmtKind::Assign { target, .. } => {
            out.slots.push(target.slot);
            out.objects.push((target.kind, target.instance));
        }
        StmtKind::Act { target, .. } => out.objects.push((target.kind, target.instance)),
        StmtKind::For { var, .. } => out.slots.push(var.slot),
        StmtKind::SetElement { place, .. } => out.slots.push(place.base.slot),
        StmtKind::Read(places) => places.iter().for_each(|p| place_slot(p, out)),
        StmtKind::Swap(a, b) => {
            place_slot(a, out);
            place_slot(b, out);
        }
        StmtKind::MidSet { place, .. } => place_slot(place, out),
        // RANDOMIZE changes what RND gives.
        StmtKind::Randomize(_) => out.slots.push(RANDOM),
        _ => {}
    });
}

/// Stands for the random-number generator among the slots: RND reads it, RANDOMIZE writes it.
const RANDOM: SlotId = SlotId::MAX;

/// The slot a place writes (an array's first element for any of its elements).
fn place_slot(p: &crate::check::typed::Place, out: &mut Touched) {
    match p {
        crate::check::typed::Place::Var(r) => out.slots.push(r.slot),
        crate::check::typed::Place::Element(el) => out.slots.push(el.base.slot),
    }
}

/// What `e` reads.
fn expr_reads(e: &Expr, out: &mut Touched) {
    match &e.kind {
        ExprKind::Read { target, .. } => {
            out.slots.push(target.slot);
            out.objects.push((target.kind, target.instance));
        }
        ExprKind::Neg(x) | ExprKind::Not(x) | ExprKind::BitNot(x) | ExprKind::Paren(x) => {
            expr_reads(x, out)
        }
        ExprKind::Binary { a, b, .. } => {
            expr_reads(a, out);
            expr_reads(b, out);
        }
        ExprKind::Call(_, args) | ExprKind::AxisSet(args) => {
            for a in args {
                expr_reads(a, out);
            }
        }
        ExprKind::Kernel { args, .. } => {
            for a in args {
                expr_reads(a, out);
            }
        }
        ExprKind::AxisRead { axes, .. } => expr_reads(axes, out),
        ExprKind::Element(el) => {
            out.slots.push(el.base.slot);
            out.objects.push((el.base.kind, el.base.instance));
            for a in &el.subs {
                expr_reads(a, out);
            }
        }
        ExprKind::Text(_, args) => {
            for a in args {
                expr_reads(a, out);
            }
        }
        ExprKind::Rnd(a) => {
            out.slots.push(RANDOM);
            if let Some(a) = a {
                expr_reads(a, out);
            }
        }
        ExprKind::Timer => {}
        ExprKind::Const(_) | ExprKind::Bool { .. } | ExprKind::Str(_) => {}
    }
}
