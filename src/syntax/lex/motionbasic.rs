//! The MotionBASIC lexer (logos): its keywords, case-insensitive, turned into the tokens both
//! dialects' grammar reads. Newlines end statements; `:` separates statements on a line. Names
//! carry their type suffix (`PLEN&`, `knife~`, `POS.ASEN@`) and may contain dots; `NAME:` at
//! the start of a line is a label.

use super::super::token::{LexError, Tok};
use logos::Logos;

/// One word of a MotionBASIC program.
#[derive(Logos, Debug, Clone, Copy, PartialEq)]
#[logos(error = LexError)]
#[logos(skip r"[ \t\r\f\x{FEFF}]+")]
#[logos(skip(r"['‘’][^\n]*", allow_greedy = true))]
enum MbLex<'s> {
    #[token("\n")]
    Newline,
    /// A number as written: a type suffix and a `D` exponent are part of it, and `&H`/`&O`
    /// integers (read by `lines::literal`).
    #[regex(r"[0-9]+(\.[0-9]*)?([eEdD][+-]?[0-9]+)?[%&!#]?", |lex| lex.slice())]
    #[regex(r"\.[0-9]+([eEdD][+-]?[0-9]+)?[%&!#]?", |lex| lex.slice())]
    #[regex(r"&[Hh][0-9A-Fa-f]+&?", |lex| lex.slice())]
    #[regex(r"&[Oo]?[0-7]+&?", |lex| lex.slice())]
    Number(&'s str),
    /// A string literal, quotes excluded.
    #[regex(r#""[^"\n]*""#, |lex| { let s = lex.slice(); &s[1..s.len() - 1] })]
    Str(&'s str),
    /// A name with its optional type suffix: `PLEN.TMP&`, `web~`, `POS.ASEN@`, `MP.CONFIG`.
    #[regex(r"[A-Za-z][A-Za-z0-9_.]*[&~@%!#$]?", |lex| lex.slice())]
    Name(&'s str),
    /// A `REM` comment (dropped by [`lex`]).
    #[regex(r"(?i:rem)([ \t][^\n]*)?", priority = 10, allow_greedy = true)]
    Rem,
    #[token("if", ignore(case))]
    If,
    #[token("then", ignore(case))]
    Then,
    #[token("else", ignore(case))]
    Else,
    #[token("elseif", ignore(case))]
    ElseIf,
    #[token("endif", ignore(case))]
    Endif,
    #[token("while", ignore(case))]
    While,
    #[token("whiletrue", ignore(case))]
    WhileTrue,
    #[token("wend", ignore(case))]
    Wend,
    #[token("do", ignore(case))]
    Do,
    #[token("loop", ignore(case))]
    Loop,
    #[token("until", ignore(case))]
    Until,
    #[token("exit", ignore(case))]
    Exit,
    #[token("select", ignore(case))]
    Select,
    /// Microsoft BASIC's words for error trapping, user functions and procedures, which
    /// pacer does not run (reserved words there, so never a variable's name).
    #[token("error", |lex| lex.slice(), ignore(case))]
    #[token("resume", |lex| lex.slice(), ignore(case))]
    #[token("err", |lex| lex.slice(), ignore(case))]
    #[token("erl", |lex| lex.slice(), ignore(case))]
    #[token("def", |lex| lex.slice(), ignore(case))]
    #[token("sub", |lex| lex.slice(), ignore(case))]
    #[token("function", |lex| lex.slice(), ignore(case))]
    Unsupported(&'s str),
    #[token("case", ignore(case))]
    Case,
    #[token("is", ignore(case))]
    Is,
    #[token("const", ignore(case))]
    Const,
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
    /// `ON n GOTO …` / `ON n GOSUB …` (a keyword, never a value, as in Microsoft BASIC).
    #[token("on", ignore(case))]
    On,
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
    #[token("print", ignore(case))]
    #[token("?")]
    Print,
    #[token("dim", ignore(case))]
    Dim,
    /// `PRINT USING`.
    #[token("using", ignore(case))]
    Using,
    /// `DATA` and its items: everything up to the end of the line or a `:` outside quotes
    /// (unquoted items are text, as in Microsoft BASIC).
    #[regex(r#"(?i:data)([ \t]([^\n:"]|"[^"\n]*")*)?"#, |lex| lex.slice(), allow_greedy = true)]
    Data(&'s str),
    #[token("read", ignore(case))]
    Read,
    #[token("restore", ignore(case))]
    Restore,
    #[token("swap", ignore(case))]
    Swap,
    #[token("randomize", ignore(case))]
    Randomize,
    #[token("let", ignore(case))]
    Let,
    #[regex(r"(?i:def(int|lng|sng|dbl|str))", |lex| lex.slice())]
    DefType(&'s str),
    /// `OPTION BASE`: one token, so `OPTION` and `BASE` stay names a program may use.
    #[regex(r"(?i:option[ \t]+base)")]
    OptionBase,
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
    #[token(";")]
    Semicolon,
    #[token(":")]
    Colon,
}

type Spanned<'s> = Result<(usize, Tok<'s>, usize), LexError>;

/// The token stream lalrpop consumes. A name that starts a line and is followed by `:` becomes
/// one [`Tok::Label`] (as in QuickBASIC), so `MAIN:` is a label and `A = 1 : B = 2` is two
/// statements.
pub fn lex(src: &str) -> impl Iterator<Item = Spanned<'_>> {
    let mut raw = MbLex::lexer(src)
        .spanned()
        .filter_map(move |(res, span)| match res {
            Ok(word) => token(word).map(|t| (span.start, t, span.end)),
            Err(LexError) => Some((
                span.start,
                Tok::Bad(src.get(span.clone()).unwrap_or("?")),
                span.end,
            )),
        })
        .peekable();
    let mut line_start = true;
    let mut print = PrintItems::default();
    let mut held: Option<(usize, Tok<'_>, usize)> = None;
    std::iter::from_fn(move || {
        if let Some(t) = held.take() {
            return Some(Ok(t));
        }
        let (l, mut tok, mut r) = raw.next()?;
        // `PickPlace.alrActPos[3]`: an index right after a dotted name is part of the name.
        if let Tok::Name(n) = tok {
            if let Some(end) = indexed_name_end(src, n, r) {
                while raw.peek().is_some_and(|t| t.0 < end) {
                    raw.next();
                }
                tok = Tok::Name(src.get(l..end).unwrap_or(n));
                r = end;
            }
        }
        let at_start = line_start;
        line_start = matches!(tok, Tok::Newline);
        if let (true, Tok::Name(n)) = (at_start, tok) {
            if let Some(&(_, Tok::Colon, cr)) = raw.peek() {
                raw.next();
                return Some(Ok((l, Tok::Label(n), cr)));
            }
        }
        if let Some(at) = print.next(tok, r) {
            held = Some((l, tok, r));
            return Some(Ok((at, Tok::Semicolon, at)));
        }
        Some(Ok((l, tok, r)))
    })
}

/// Microsoft BASIC prints two items written side by side as if `;` were between them
/// (`PRINT "COUNT=" C%` is `PRINT "COUNT="; C%`). Inside a PRINT statement, an item that ends
/// (a literal, a name, `)`) followed by one that starts with a literal or a name — which no
/// expression can continue with — gets the `;` it implies, at the end of the first item. A sign
/// or a parenthesis after an item still continues the expression (`PRINT A -B`, `PRINT A (1)`),
/// as in Microsoft BASIC.
#[derive(Debug, Default)]
struct PrintItems {
    /// Inside a PRINT statement.
    inside: bool,
    /// Where the item just read ends, when the last token ended one.
    item_end: Option<usize>,
}

impl PrintItems {
    /// See `tok` (ending at `r`); the place of a `;` to put before it, if it needs one.
    fn next(&mut self, tok: Tok<'_>, r: usize) -> Option<usize> {
        let starts_item = matches!(
            tok,
            Tok::Number(_) | Tok::Str(_) | Tok::Name(_) | Tok::True | Tok::False
        );
        let implied = if self.inside && starts_item {
            self.item_end
        } else {
            None
        };
        match tok {
            Tok::Print => self.inside = true,
            Tok::Newline | Tok::Colon | Tok::Else => self.inside = false,
            _ => {}
        }
        self.item_end = (self.inside && (starts_item || tok == Tok::RParen)).then_some(r);
        implied
    }
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

/// The token a MotionBASIC word is; none for a `REM` comment.
fn token(word: MbLex<'_>) -> Option<Tok<'_>> {
    Some(match word {
        MbLex::Newline => Tok::Newline,
        MbLex::Number(s) => Tok::Number(s),
        MbLex::Str(s) => Tok::Str(s),
        MbLex::Name(s) => Tok::Name(s),
        MbLex::Rem => return None,
        MbLex::Unsupported(s) => Tok::Unsupported(s),
        MbLex::If => Tok::If,
        MbLex::Then => Tok::Then,
        MbLex::Else => Tok::Else,
        MbLex::Do => Tok::Do,
        MbLex::Loop => Tok::Loop,
        MbLex::Until => Tok::Until,
        MbLex::Exit => Tok::Exit,
        MbLex::Select => Tok::Select,
        MbLex::Case => Tok::Case,
        MbLex::Is => Tok::Is,
        MbLex::Const => Tok::Const,
        MbLex::ElseIf => Tok::ElseIf,
        MbLex::Endif => Tok::Endif,
        MbLex::While => Tok::While,
        MbLex::WhileTrue => Tok::WhileTrue,
        MbLex::Wend => Tok::Wend,
        MbLex::For => Tok::For,
        MbLex::To => Tok::To,
        MbLex::Step => Tok::Step,
        MbLex::Next => Tok::Next,
        MbLex::Gosub => Tok::Gosub,
        MbLex::Goto => Tok::Goto,
        MbLex::On => Tok::On,
        MbLex::Return => Tok::Return,
        MbLex::End => Tok::End,
        MbLex::Gear => Tok::Gear,
        MbLex::Move => Tok::Move,
        MbLex::At => Tok::At,
        MbLex::In => Tok::In,
        MbLex::After => Tok::After,
        MbLex::Print => Tok::Print,
        MbLex::Dim => Tok::Dim,
        MbLex::Using => Tok::Using,
        MbLex::Data(s) => Tok::Data(s),
        MbLex::Read => Tok::Read,
        MbLex::Restore => Tok::Restore,
        MbLex::Swap => Tok::Swap,
        MbLex::Randomize => Tok::Randomize,
        MbLex::Let => Tok::Let,
        MbLex::DefType(s) => Tok::DefType(s),
        MbLex::OptionBase => Tok::OptionBase,
        MbLex::True => Tok::True,
        MbLex::False => Tok::False,
        MbLex::Not => Tok::Not,
        MbLex::And => Tok::And,
        MbLex::Or => Tok::Or,
        MbLex::Xor => Tok::Xor,
        MbLex::Mod => Tok::Mod,
        MbLex::Eq => Tok::Eq,
        MbLex::Ne => Tok::Ne,
        MbLex::Lt => Tok::Lt,
        MbLex::Le => Tok::Le,
        MbLex::Gt => Tok::Gt,
        MbLex::Ge => Tok::Ge,
        MbLex::Plus => Tok::Plus,
        MbLex::Minus => Tok::Minus,
        MbLex::Star => Tok::Star,
        MbLex::Slash => Tok::Slash,
        MbLex::Backslash => Tok::Backslash,
        MbLex::Caret => Tok::Caret,
        MbLex::LParen => Tok::LParen,
        MbLex::RParen => Tok::RParen,
        MbLex::LBracket => Tok::LBracket,
        MbLex::RBracket => Tok::RBracket,
        MbLex::LBrace => Tok::LBrace,
        MbLex::RBrace => Tok::RBrace,
        MbLex::Comma => Tok::Comma,
        MbLex::Semicolon => Tok::Semicolon,
        MbLex::Colon => Tok::Colon,
    })
}
