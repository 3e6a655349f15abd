//! The PowerTools lexer (logos): its keywords, case-insensitive, and its boolean words, turned
//! into the tokens both dialects' grammar reads. Newlines are tokens: a newline ends a
//! statement.

use super::super::token::{LexError, Tok};
use logos::Logos;

/// One word of a PowerTools program.
#[derive(Logos, Debug, Clone, Copy, PartialEq)]
#[logos(error = LexError)]
#[logos(skip r"[ \t\r\f\x{FEFF}]+")]
// Comments run to the end of the line; typeset manuals show curly quotes too.
#[logos(skip(r"['‘’][^\n]*", allow_greedy = true))]
enum PtLex<'s> {
    #[token("\n")]
    Newline,
    #[regex(r"[0-9]+(\.[0-9]*)?([eE][+-]?[0-9]+)?", |lex| lex.slice())]
    #[regex(r"\.[0-9]+([eE][+-]?[0-9]+)?", |lex| lex.slice())]
    Number(&'s str),
    /// A plain or dotted name: `Var.Count`, `Queue.0.QueueEmpty`, `MyLabel`. A segment after a
    /// dot may end with an index in brackets, part of the name: `PickPlace.alrActPos[3]`.
    #[regex(r"[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z0-9_]+(\[[0-9]+\])?)*", |lex| lex.slice())]
    Name(&'s str),

    #[token("wait", ignore(case))]
    Wait,
    #[token("for", ignore(case))]
    For,
    #[token("time", ignore(case))]
    Time,
    #[token("dwell", ignore(case))]
    Dwell,
    #[token("master", ignore(case))]
    Master,
    #[token("dist", ignore(case))]
    Dist,
    #[token("if", ignore(case))]
    If,
    #[token("then", ignore(case))]
    Then,
    #[token("else", ignore(case))]
    Else,
    #[token("endif", ignore(case))]
    Endif,
    #[token("do", ignore(case))]
    Do,
    #[token("while", ignore(case))]
    While,
    #[token("loop", ignore(case))]
    Loop,
    #[token("end", ignore(case))]
    End,
    #[token("using", ignore(case))]
    Using,
    #[token("last", ignore(case))]
    Last,
    #[token("on", ignore(case))]
    On,
    #[token("to", ignore(case))]
    To,
    #[token("step", ignore(case))]
    Step,
    #[token("next", ignore(case))]
    Next,
    #[token("goto", ignore(case))]
    Goto,
    #[token("jump", ignore(case))]
    Jump,
    #[token("call", ignore(case))]
    Call,
    #[token("true", ignore(case))]
    #[token("yes", ignore(case))]
    #[token("set", ignore(case))]
    #[token("enable", ignore(case))]
    True,
    #[token("off", ignore(case))]
    #[token("false", ignore(case))]
    #[token("no", ignore(case))]
    #[token("clear", ignore(case))]
    #[token("disable", ignore(case))]
    False,
    #[token("not", ignore(case))]
    Not,
    #[token("and", ignore(case))]
    And,
    #[token("or", ignore(case))]
    Or,
    #[token("xor", ignore(case))]
    Xor,
    #[token("mod", ignore(case))]
    Mod,

    #[token("=")]
    Eq,
    #[token("<>")]
    Ne,
    #[token("<")]
    Lt,
    #[token("<=")]
    Le,
    #[token(">")]
    Gt,
    #[token(">=")]
    Ge,
    #[token("+")]
    Plus,
    #[token("-")]
    Minus,
    #[token("*")]
    Star,
    #[token("/")]
    Slash,
    #[token("^")]
    Caret,
    #[token("(")]
    LParen,
    #[token(")")]
    RParen,
    #[token(",")]
    Comma,
    #[token(":")]
    Colon,
}

/// The token stream lalrpop consumes: `(start, token, end)` triples.
pub fn lex(src: &str) -> impl Iterator<Item = Result<(usize, Tok<'_>, usize), LexError>> {
    PtLex::lexer(src)
        .spanned()
        .map(move |(res, span)| match res {
            Ok(word) => Ok((span.start, token(word), span.end)),
            Err(LexError) => Ok((
                span.start,
                Tok::Bad(src.get(span.clone()).unwrap_or("?")),
                span.end,
            )),
        })
}

/// The token a PowerTools word is.
fn token(word: PtLex<'_>) -> Tok<'_> {
    match word {
        PtLex::Newline => Tok::Newline,
        PtLex::Number(s) => Tok::Number(s),
        PtLex::Name(s) => Tok::Name(s),
        PtLex::Wait => Tok::Wait,
        PtLex::For => Tok::For,
        PtLex::Time => Tok::Time,
        PtLex::Dwell => Tok::Dwell,
        PtLex::Master => Tok::Master,
        PtLex::Dist => Tok::Dist,
        PtLex::If => Tok::If,
        PtLex::Then => Tok::Then,
        PtLex::Else => Tok::Else,
        PtLex::Endif => Tok::Endif,
        PtLex::Do => Tok::Do,
        PtLex::While => Tok::While,
        PtLex::Loop => Tok::Loop,
        PtLex::End => Tok::End,
        PtLex::Using => Tok::Using,
        PtLex::Last => Tok::Last,
        PtLex::On => Tok::On,
        PtLex::To => Tok::To,
        PtLex::Step => Tok::Step,
        PtLex::Next => Tok::Next,
        PtLex::Goto => Tok::Goto,
        PtLex::Jump => Tok::Jump,
        PtLex::Call => Tok::Call,
        PtLex::True => Tok::True,
        PtLex::False => Tok::False,
        PtLex::Not => Tok::Not,
        PtLex::And => Tok::And,
        PtLex::Or => Tok::Or,
        PtLex::Xor => Tok::Xor,
        PtLex::Mod => Tok::Mod,
        PtLex::Eq => Tok::Eq,
        PtLex::Ne => Tok::Ne,
        PtLex::Lt => Tok::Lt,
        PtLex::Le => Tok::Le,
        PtLex::Gt => Tok::Gt,
        PtLex::Ge => Tok::Ge,
        PtLex::Plus => Tok::Plus,
        PtLex::Minus => Tok::Minus,
        PtLex::Star => Tok::Star,
        PtLex::Slash => Tok::Slash,
        PtLex::Caret => Tok::Caret,
        PtLex::LParen => Tok::LParen,
        PtLex::RParen => Tok::RParen,
        PtLex::Comma => Tok::Comma,
        PtLex::Colon => Tok::Colon,
    }
}
