//! The two dialects' lexers: each reads its own keywords and comments and makes the tokens the
//! shared grammar reads.

pub mod motionbasic;
pub mod powertools;

use super::token::{LexError, Tok};
use super::Dialect;

/// `(start, token, end)` triples, as lalrpop consumes them.
pub type Spanned<'s> = Result<(usize, Tok<'s>, usize), LexError>;

/// The tokens of `src` in `dialect`.
pub fn lex(src: &str, dialect: Dialect) -> Box<dyn Iterator<Item = Spanned<'_>> + '_> {
    match dialect {
        Dialect::PowerTools => Box::new(powertools::lex(src)),
        Dialect::MotionBasic => Box::new(motionbasic::lex(src)),
    }
}
