//! The PowerTools token set (logos). Newlines are tokens: a newline ends a statement.

use logos::Logos;

/// Raised by logos for a character that starts no token; the lexer turns it into [`Tok::Bad`]
/// so the parser reports it in place and recovers.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct LexError;

/// One token of a PowerTools program.
#[derive(Logos, Debug, Clone, Copy, PartialEq)]
#[logos(error = LexError)]
#[logos(skip r"[ \t\r\f\x{FEFF}]+")]
// Comments run to the end of the line; typeset manuals show curly quotes too.
#[logos(skip(r"['‘’][^\n]*", allow_greedy = true))]
pub enum Tok<'s> {
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
    TrueWord,
    #[token("off", ignore(case))]
    #[token("false", ignore(case))]
    #[token("no", ignore(case))]
    #[token("clear", ignore(case))]
    #[token("disable", ignore(case))]
    FalseWord,
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
    /// Text that starts no token (made by [`lex`], never by logos itself).
    Bad(&'s str),
}

impl std::fmt::Display for Tok<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let s = match self {
            Tok::Newline => "end of line",
            Tok::Number(s) | Tok::Name(s) => return write!(f, "`{s}`"),
            Tok::Wait => "Wait",
            Tok::For => "For",
            Tok::Time => "Time",
            Tok::Dwell => "Dwell",
            Tok::Master => "Master",
            Tok::Dist => "Dist",
            Tok::If => "If",
            Tok::Then => "Then",
            Tok::Else => "Else",
            Tok::Endif => "Endif",
            Tok::Do => "Do",
            Tok::While => "While",
            Tok::Loop => "Loop",
            Tok::End => "End",
            Tok::Using => "Using",
            Tok::Last => "Last",
            Tok::On => "ON",
            Tok::To => "To",
            Tok::Step => "Step",
            Tok::Next => "Next",
            Tok::Goto => "Goto",
            Tok::Jump => "Jump",
            Tok::Call => "Call",
            Tok::TrueWord => "a boolean word (ON/TRUE/YES/SET/ENABLE)",
            Tok::FalseWord => "a boolean word (OFF/FALSE/NO/CLEAR/DISABLE)",
            Tok::Not => "NOT",
            Tok::And => "AND",
            Tok::Or => "OR",
            Tok::Xor => "XOR",
            Tok::Mod => "MOD",
            Tok::Eq => "`=`",
            Tok::Ne => "`<>`",
            Tok::Lt => "`<`",
            Tok::Le => "`<=`",
            Tok::Gt => "`>`",
            Tok::Ge => "`>=`",
            Tok::Plus => "`+`",
            Tok::Minus => "`-`",
            Tok::Star => "`*`",
            Tok::Slash => "`/`",
            Tok::Caret => "`^`",
            Tok::LParen => "`(`",
            Tok::RParen => "`)`",
            Tok::Comma => "`,`",
            Tok::Colon => "`:`",
            Tok::Bad(s) => return write!(f, "unexpected character `{s}`"),
        };
        f.write_str(s)
    }
}

/// The token stream lalrpop consumes: `(start, token, end)` triples.
pub fn lex(src: &str) -> impl Iterator<Item = Result<(usize, Tok<'_>, usize), LexError>> {
    Tok::lexer(src).spanned().map(move |(res, span)| match res {
        Ok(tok) => Ok((span.start, tok, span.end)),
        Err(LexError) => Ok((
            span.start,
            Tok::Bad(src.get(span.clone()).unwrap_or("?")),
            span.end,
        )),
    })
}
