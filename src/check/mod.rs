//! The checker: one walk for both dialects ([`walk`]: statements, blocks, labels, jumps), with
//! each dialect's rules behind a trait ([`powertools`], [`motionbasic`]: how names resolve, how
//! expressions are typed, which statements it has). It reports every problem of a file (not
//! only the first) and gives the compiler a resolved, typed program ([`typed`]).

pub mod functions;
pub mod loops;
pub mod machine;
pub mod motionbasic;
pub mod powertools;
pub mod text;
pub mod typed;
pub mod walk;

use crate::diag::Problem;
use crate::syntax::ast::{Expr, ProgramAst};
use crate::syntax::Dialect;
pub use motionbasic::Variables;
pub use typed::Ty;

/// What the checker needs to know about the machine: its objects and the programs loaded.
pub type CheckEnv<'a> = walk::Machine<'a>;

/// Check a program of `dialect` against the machine; `variables` are every MotionBASIC
/// program's variables. The checked program (complete when there is no error) and every
/// problem.
pub fn check(
    ast: &ProgramAst,
    dialect: Dialect,
    env: &CheckEnv<'_>,
    variables: &Variables,
) -> (typed::Program, Vec<Problem>) {
    let (program, mut problems) = match dialect {
        Dialect::PowerTools => walk::check(&mut powertools::PowerTools, env, ast),
        Dialect::MotionBasic => {
            walk::check(&mut motionbasic::MotionBasic::new(variables), env, ast)
        }
    };
    // MotionBASIC has no `Wait For`: a `WHILE … : WEND` poll is its idiom.
    if dialect == Dialect::PowerTools {
        loops::busy_loops(&program, &mut problems);
    }
    (program, problems)
}

/// Check one expression of `dialect` (a line typed at the REPL): its typed form (when it has no
/// error) and every problem. A MotionBASIC expression must be a number or a string.
pub fn check_expr(
    e: &Expr,
    dialect: Dialect,
    env: &CheckEnv<'_>,
    variables: &Variables,
) -> (Option<typed::Expr>, Vec<Problem>) {
    let mut cx = walk::Context {
        machine: env,
        problems: Vec::new(),
        labels: Default::default(),
    };
    let typed = match dialect {
        Dialect::PowerTools => {
            walk::Rules::expr(&mut powertools::PowerTools, &mut cx, e, walk::Want::Any)
        }
        Dialect::MotionBasic => {
            let mut rules = motionbasic::MotionBasic::new(variables);
            match walk::Rules::expr(&mut rules, &mut cx, e, walk::Want::Any) {
                Some(t) if t.ty == Ty::Str => Some(t),
                // Anything else must be a number (an axis set is shown as its error).
                Some(_) => {
                    cx.problems.clear();
                    walk::Rules::expr(&mut rules, &mut cx, e, walk::Want::Number("a number"))
                }
                None => None,
            }
        }
    };
    let failed = cx
        .problems
        .iter()
        .any(|p| p.level == crate::diag::Level::Error);
    (typed.filter(|_| !failed), cx.problems)
}

/// Check a PowerTools program; every problem found.
pub fn check_program(ast: &ProgramAst, env: &CheckEnv<'_>) -> Vec<Problem> {
    check(ast, Dialect::PowerTools, env, &Variables::default()).1
}
