//! The MotionBASIC token set (logos). Newlines end statements; `:` separates statements on a
//! line. Names carry their type suffix (`PLEN&`, `knife~`, `POS.ASEN@`) and may contain dots.

use logos::Logos;

use super::token::LexError;

/// One token of a MotionBASIC program.
#[derive(Logos, Debug, Clone, Copy, PartialEq)]
#[logos(error = LexError)]
#[logos(skip r"[ \t\r\f\x{FEFF}]+")]
#[logos(skip(r"['‘’][^\n]*", allow_greedy = true))]
pub enum MbTok<'s> {
    #[token("\n")]
    Newline,
    #[regex(r"[0-9]+(\.[0-9]*)?([eE][+-]?[0-9]+)?", |lex| lex.slice())]
    #[regex(r"\.[0-9]+([eE][+-]?[0-9]+)?", |lex| lex.slice())]
    Number(&'s str),
    /// A string literal, quotes excluded.
    #[regex(r#""[^"\n]*""#, |lex| { let s = lex.slice(); &s[1..s.len() - 1] })]
    Str(&'s str),
    /// A name with its optional type suffix: `PLEN.TMP&`, `web~`, `POS.ASEN@`, `MP.CONFIG`.
    #[regex(r"[A-Za-z][A-Za-z0-9_.]*[&~@%!#$]?", |lex| lex.slice())]
    Name(&'s str),
    /// `NAME:` at the start of a line (made by [`lex`] from a name and a colon).
    Label(&'s str),
    /// A `REM` comment (dropped by [`lex`]).
    #[regex(r"(?i:rem)([ \t][^\n]*)?", priority = 10, allow_greedy = true)]
    Rem,
    #[token("if", ignore(case))]
    If,
    #[token("then", ignore(case))]
    Then,
    #[token("else", ignore(case))]
    Else,
    #[token("endif", ignore(case))]
    Endif,
    #[token("while", ignore(case))]
    While,
    #[token("whiletrue", ignore(case))]
    WhileTrue,
    #[token("wend", ignore(case))]
    Wend,
    #[token("for", ignore(case))]
    For,
    #[token("to", ignore(case))]
    To,
    #[token("step", ignore(case))]
    Step,
    #[token("next", ignore(case))]
    Next,
    #[token("gosub", ignore(case))]
    Gosub,
    #[token("goto", ignore(case))]
    Goto,
    #[token("return", ignore(case))]
    Return,
    #[token("end", ignore(case))]
    End,
    #[token("gear", ignore(case))]
    Gear,
    #[token("move", ignore(case))]
    Move,
    #[token("at", ignore(case))]
    At,
    #[token("in", ignore(case))]
    In,
    #[token("after", ignore(case))]
    After,
    #[token("true", ignore(case))]
    True,
    #[token("false", ignore(case))]
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
    #[token("><")]
    Ne,
    #[token("<")]
    Lt,
    #[token("<=")]
    #[token("=<")]
    Le,
    #[token(">")]
    Gt,
    #[token(">=")]
    #[token("=>")]
    Ge,
    #[token("+")]
    Plus,
    #[token("-")]
    Minus,
    #[token("*")]
    Star,
    #[token("/")]
    Slash,
    #[token("\\")]
    Backslash,
    #[token("^")]
    Caret,
    #[token("(")]
    LParen,
    #[token(")")]
    RParen,
    #[token("[")]
    LBracket,
    #[token("]")]
    RBracket,
    #[token("{")]
    LBrace,
    #[token("}")]
    RBrace,
    #[token(",")]
    Comma,
    #[token(":")]
    Colon,
    /// Text that starts no token (made by [`lex`], never by logos itself).
    Bad(&'s str),
}

impl std::fmt::Display for MbTok<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let s = match self {
            MbTok::Newline => "end of line",
            MbTok::Number(s) | MbTok::Name(s) => return write!(f, "`{s}`"),
            MbTok::Str(s) => return write!(f, "the string \"{s}\""),
            MbTok::Label(s) => return write!(f, "the label `{s}:`"),
            MbTok::Rem => "REM",
            MbTok::If => "IF",
            MbTok::Then => "THEN",
            MbTok::Else => "ELSE",
            MbTok::Endif => "ENDIF",
            MbTok::While => "WHILE",
            MbTok::WhileTrue => "WHILETRUE",
            MbTok::Wend => "WEND",
            MbTok::For => "FOR",
            MbTok::To => "TO",
            MbTok::Step => "STEP",
            MbTok::Next => "NEXT",
            MbTok::Gosub => "GOSUB",
            MbTok::Goto => "GOTO",
            MbTok::Return => "RETURN",
            MbTok::End => "END",
            MbTok::Gear => "GEAR",
            MbTok::Move => "MOVE",
            MbTok::At => "AT",
            MbTok::In => "IN",
            MbTok::After => "AFTER",
            MbTok::True => "TRUE",
            MbTok::False => "FALSE",
            MbTok::Not => "NOT",
            MbTok::And => "AND",
            MbTok::Or => "OR",
            MbTok::Xor => "XOR",
            MbTok::Mod => "MOD",
            MbTok::Eq => "`=`",
            MbTok::Ne => "`<>`",
            MbTok::Lt => "`<`",
            MbTok::Le => "`<=`",
            MbTok::Gt => "`>`",
            MbTok::Ge => "`>=`",
            MbTok::Plus => "`+`",
            MbTok::Minus => "`-`",
            MbTok::Star => "`*`",
            MbTok::Slash => "`/`",
            MbTok::Backslash => "`\\`",
            MbTok::Caret => "`^`",
            MbTok::LParen => "`(`",
            MbTok::RParen => "`)`",
            MbTok::LBracket => "`[`",
            MbTok::RBracket => "`]`",
            MbTok::LBrace => "`{`",
            MbTok::RBrace => "`}`",
            MbTok::Comma => "`,`",
            MbTok::Colon => "`:`",
            MbTok::Bad(s) => return write!(f, "unexpected character `{s}`"),
        };
        f.write_str(s)
    }
}

type Spanned<'s> = Result<(usize, MbTok<'s>, usize), LexError>;

/// The token stream lalrpop consumes. A name that starts a line and is followed by `:` becomes
/// one [`MbTok::Label`] (as in QuickBASIC), so `MAIN:` is a label and `A = 1 : B = 2` is two
/// statements.
pub fn lex(src: &str) -> impl Iterator<Item = Spanned<'_>> {
    let mut raw = MbTok::lexer(src)
        .spanned()
        .map(move |(res, span)| match res {
            Ok(tok) => (span.start, tok, span.end),
            Err(LexError) => (
                span.start,
                MbTok::Bad(src.get(span.clone()).unwrap_or("?")),
                span.end,
            ),
        })
        .filter(|t| !matches!(t.1, MbTok::Rem))
        .peekable();
    let mut line_start = true;
    std::iter::from_fn(move || {
        let (l, mut tok, mut r) = raw.next()?;
        // `PickPlace.alrActPos[3]`: an index right after a dotted name is part of the name.
        if let MbTok::Name(n) = tok {
            if let Some(end) = indexed_name_end(src, n, r) {
                while raw.peek().is_some_and(|t| t.0 < end) {
                    raw.next();
                }
                tok = MbTok::Name(src.get(l..end).unwrap_or(n));
                r = end;
            }
        }
        let at_start = line_start;
        line_start = matches!(tok, MbTok::Newline);
        if let (true, MbTok::Name(n)) = (at_start, tok) {
            if let Some(&(_, MbTok::Colon, cr)) = raw.peek() {
                raw.next();
                return Some(Ok((l, MbTok::Label(n), cr)));
            }
        }
        Some(Ok((l, tok, r)))
    })
}

/// Where a dotted name `n` ending at `r` ends when `[digits]` follows it with no space
/// (`Belt.2.ascInitialObjectPosition[1]`); None otherwise, so `[ ]` elsewhere still groups
/// like `( )`.
fn indexed_name_end(src: &str, n: &str, r: usize) -> Option<usize> {
    if !n.contains('.') || !n.ends_with(|c: char| c.is_ascii_alphanumeric() || c == '_') {
        return None;
    }
    let rest = src.get(r..)?.strip_prefix('[')?;
    let digits = rest.bytes().take_while(u8::is_ascii_digit).count();
    (digits > 0 && rest[digits..].starts_with(']')).then_some(r + digits + 2)
}
