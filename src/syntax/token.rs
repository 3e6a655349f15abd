//! The tokens the grammar reads, for both dialects: each dialect's lexer (`lex/`) makes them
//! from its own keywords, so a token a dialect does not have is simply never made by its lexer.
//! Messages name a token as its dialect writes it ([`Tok::describe`]).

use super::Dialect;
use std::borrow::Cow;

/// Raised by logos for a character that starts no token; the lexers turn it into [`Tok::Bad`]
/// so the parser reports it in place and recovers.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct LexError;

/// One token of a program, in either dialect.
#[derive(Debug, Clone, Copy, PartialEq)]
#[allow(missing_docs)]
pub enum Tok<'s> {
    /// A newline ends a statement.
    Newline,
    Number(&'s str),
    /// A string literal, quotes excluded (MotionBASIC).
    Str(&'s str),
    /// A plain or dotted name: `Var.Count`, `Queue.0.QueueEmpty`, `PLEN&`, `POS.ASEN@`.
    Name(&'s str),
    /// `NAME:` at the start of a line (MotionBASIC).
    Label(&'s str),
    Wait,
    For,
    Time,
    Dwell,
    Master,
    Dist,
    If,
    Then,
    Else,
    /// `ELSEIF` (MotionBASIC).
    ElseIf,
    Endif,
    Do,
    While,
    WhileTrue,
    Wend,
    Loop,
    /// `UNTIL` (MotionBASIC `DO UNTIL`, `LOOP UNTIL`).
    Until,
    /// `EXIT` (MotionBASIC `EXIT FOR`, `EXIT DO`).
    Exit,
    /// `SELECT` (MotionBASIC `SELECT CASE`).
    Select,
    /// `CASE` (MotionBASIC `SELECT CASE`, `CASE …`, `CASE ELSE`).
    Case,
    /// `IS` (MotionBASIC `CASE IS > 5`).
    Is,
    /// `CONST` (MotionBASIC).
    Const,
    /// A Microsoft BASIC keyword pacer knows but does not run (MotionBASIC `ON ERROR GOTO`,
    /// `RESUME`, `DEF FN`, `SUB` …): the grammar takes none, so a program using one is refused
    /// at it with a message saying so ([`crate::registry::not_yet::basic`]).
    Unsupported(&'s str),
    End,
    Using,
    Last,
    On,
    To,
    Step,
    Next,
    Goto,
    Jump,
    Call,
    Gosub,
    Return,
    Gear,
    Move,
    At,
    In,
    After,
    /// `PRINT` or `?` (MotionBASIC).
    Print,
    /// `DIM` (MotionBASIC).
    Dim,
    /// `DATA` and the raw text of its items up to the end of the statement (MotionBASIC).
    Data(&'s str),
    /// `READ` (MotionBASIC).
    Read,
    /// `RESTORE` (MotionBASIC).
    Restore,
    /// `SWAP` (MotionBASIC).
    Swap,
    /// `RANDOMIZE` (MotionBASIC).
    Randomize,
    /// `LET` (MotionBASIC).
    Let,
    /// `DEFINT`, `DEFLNG`, `DEFSNG`, `DEFDBL` or `DEFSTR`, as written (MotionBASIC).
    DefType(&'s str),
    /// `OPTION BASE` (MotionBASIC).
    OptionBase,
    /// A word for ON: `TRUE` in MotionBASIC; `TRUE`, `YES`, `SET`, `ENABLE` in PowerTools.
    True,
    /// A word for OFF: `FALSE` in MotionBASIC; `OFF`, `FALSE`, `NO`, `CLEAR`, `DISABLE` in
    /// PowerTools.
    False,
    Not,
    And,
    Or,
    Xor,
    Mod,
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
    Plus,
    Minus,
    Star,
    Slash,
    Backslash,
    Caret,
    LParen,
    RParen,
    LBracket,
    RBracket,
    LBrace,
    RBrace,
    Comma,
    /// `;` (MotionBASIC: a PRINT separator).
    Semicolon,
    Colon,
    /// Text that starts no token.
    Bad(&'s str),
}

impl Tok<'_> {
    /// The token as messages in `dialect` name it.
    pub fn describe(&self, dialect: Dialect) -> Cow<'static, str> {
        let basic = dialect == Dialect::MotionBasic;
        // Keywords: PowerTools writes them capitalized, MotionBASIC in capitals.
        let word = |pt: &'static str| -> Cow<'static, str> {
            if basic {
                Cow::Owned(pt.to_ascii_uppercase())
            } else {
                Cow::Borrowed(pt)
            }
        };
        match self {
            Tok::Newline => "end of line".into(),
            Tok::Number(s) | Tok::Name(s) => format!("`{s}`").into(),
            Tok::Str(s) => format!("the string \"{s}\"").into(),
            Tok::Label(s) => format!("the label `{s}:`").into(),
            Tok::Bad(s) => format!("unexpected character `{}`", crate::diag::escaped(s)).into(),
            Tok::Wait => word("Wait"),
            Tok::For => word("For"),
            Tok::Time => word("Time"),
            Tok::Dwell => word("Dwell"),
            Tok::Master => word("Master"),
            Tok::Dist => word("Dist"),
            Tok::If => word("If"),
            Tok::Then => word("Then"),
            Tok::Else => word("Else"),
            Tok::ElseIf => word("ElseIf"),
            Tok::Endif => word("Endif"),
            Tok::Do => word("Do"),
            Tok::While => word("While"),
            Tok::WhileTrue => word("WhileTrue"),
            Tok::Wend => word("Wend"),
            Tok::Loop => word("Loop"),
            Tok::Until => word("Until"),
            Tok::Exit => word("Exit"),
            Tok::Select => word("Select"),
            Tok::Case => word("Case"),
            Tok::Is => word("Is"),
            Tok::Const => word("Const"),
            Tok::Unsupported(w) => w.to_ascii_uppercase().into(),
            Tok::End => word("End"),
            Tok::Using => word("Using"),
            Tok::Last => word("Last"),
            Tok::On => "ON".into(),
            Tok::To => word("To"),
            Tok::Step => word("Step"),
            Tok::Next => word("Next"),
            Tok::Goto => word("Goto"),
            Tok::Jump => word("Jump"),
            Tok::Call => word("Call"),
            Tok::Gosub => word("Gosub"),
            Tok::Return => word("Return"),
            Tok::Gear => word("Gear"),
            Tok::Move => word("Move"),
            Tok::At => word("At"),
            Tok::In => word("In"),
            Tok::After => word("After"),
            Tok::Print => word("Print"),
            Tok::Dim => word("Dim"),
            Tok::Data(_) => word("Data"),
            Tok::Read => word("Read"),
            Tok::Restore => word("Restore"),
            Tok::Swap => word("Swap"),
            Tok::Randomize => word("Randomize"),
            Tok::Let => word("Let"),
            Tok::DefType(s) => s.to_ascii_uppercase().into(),
            Tok::OptionBase => "OPTION BASE".into(),
            Tok::True if basic => "TRUE".into(),
            Tok::True => "a boolean word (ON/TRUE/YES/SET/ENABLE)".into(),
            Tok::False if basic => "FALSE".into(),
            Tok::False => "a boolean word (OFF/FALSE/NO/CLEAR/DISABLE)".into(),
            Tok::Not => "NOT".into(),
            Tok::And => "AND".into(),
            Tok::Or => "OR".into(),
            Tok::Xor => "XOR".into(),
            Tok::Mod => "MOD".into(),
            Tok::Eq => "`=`".into(),
            Tok::Ne => "`<>`".into(),
            Tok::Lt => "`<`".into(),
            Tok::Le => "`<=`".into(),
            Tok::Gt => "`>`".into(),
            Tok::Ge => "`>=`".into(),
            Tok::Plus => "`+`".into(),
            Tok::Minus => "`-`".into(),
            Tok::Star => "`*`".into(),
            Tok::Slash => "`/`".into(),
            Tok::Backslash => "`\\`".into(),
            Tok::Caret => "`^`".into(),
            Tok::LParen => "`(`".into(),
            Tok::RParen => "`)`".into(),
            Tok::LBracket => "`[`".into(),
            Tok::RBracket => "`]`".into(),
            Tok::LBrace => "`{`".into(),
            Tok::RBrace => "`}`".into(),
            Tok::Comma => "`,`".into(),
            Tok::Semicolon => "`;`".into(),
            Tok::Colon => "`:`".into(),
        }
    }
}
